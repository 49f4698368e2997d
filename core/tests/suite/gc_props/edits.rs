//! Random structure-aware edits of an assembly, made the way the tools
//! make them (bends in the spine plane, slides along the parent's
//! surface), and wider than a careful user: resizes by 0.5 to 2, sections
//! replaced by any profile kind, children spun about their normal or
//! turned about their parent's axis, copies turned, slid or mirrored
//! (a root's copy slid along a world axis, in its own planes).

use glam::{DQuat, DVec3};
use proptest::prelude::*;
use shapewright::assembly::{
    anchor_frame, project_to_surface, propagate_edit, spine_controls, spine_size, AssemblyError,
    GcCopy, GcTransformPart,
};
use shapewright::gc::*;
use shapewright::math::fm::DetMath as _;
use shapewright::nurbs::euclidean;

/// The random numbers one op is made from (read against the assembly as
/// it is when the op is made).
#[derive(Clone, Debug)]
pub struct Seed {
    pub kind: u8,
    pub part: f64,
    pub section: f64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

pub fn seed() -> impl Strategy<Value = Seed> {
    (
        0u8..11,
        0.0..1.0f64,
        0.0..1.0f64,
        -1.0..1.0f64,
        -1.0..1.0f64,
        0.0..1.0f64,
        0.0..1.0f64,
    )
        .prop_map(|(kind, part, section, x, y, z, w)| Seed {
            kind,
            part,
            section,
            x,
            y,
            z,
            w,
        })
}

pub fn pick(x: f64, lo: usize, hi: usize) -> usize {
    (lo + (x * (hi - lo) as f64) as usize).min(hi - 1)
}

/// Largest distance of a profile's outline from its centre.
pub fn profile_radius(p: &Profile) -> f64 {
    let c = p.curve().expect("profile");
    c.control
        .iter()
        .map(|h| euclidean(*h).truncate().length())
        .fold(0.0, f64::max)
}

/// A profile of kind `k` (0..6: circle, ellipse, polygon, rectangle,
/// sketched loop, the same kind as `old`) reaching about `r` from the
/// centre; `y` shapes it.
pub fn profile_of_kind(k: usize, old: &Profile, r: f64, y: f64) -> Profile {
    let g = 0.9 + 0.1 * y.abs();
    match k {
        0 => Profile::Circle { radius: r },
        1 => Profile::Ellipse { rx: r, ry: r * g },
        2 => Profile::Polygon {
            sides: 3 + (y.abs() * 5.99) as u32,
            radius: r,
        },
        3 => Profile::Rectangle {
            width: 1.4 * r,
            height: 1.4 * r * g,
        },
        4 => Profile::Points {
            points: (0..9)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / 9.0 + y;
                    let k = r * (0.9 + 0.1 * (3.0 * a + y).fsin());
                    [k * a.fcos(), k * a.fsin()]
                })
                .collect(),
        },
        _ => scaled(old, r / profile_radius(old).max(1e-12), g),
    }
}

fn scaled(p: &Profile, f: f64, g: f64) -> Profile {
    match p {
        Profile::Circle { radius } => Profile::Circle { radius: radius * f },
        Profile::Ellipse { rx, ry } => Profile::Ellipse {
            rx: rx * f,
            ry: ry * f * g,
        },
        Profile::Rectangle { width, height } => Profile::Rectangle {
            width: width * f,
            height: height * f * g,
        },
        Profile::Polygon { sides, radius } => Profile::Polygon {
            sides: *sides,
            radius: radius * f,
        },
        other => other.clone(),
    }
}

/// How a part is moved or a copy placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Slid along the parent's surface, spun about the surface normal at
    /// the anchor by an angle (0 for a plain slide).
    Slide { spin: f64 },
    /// Turned about the parent's (straight) spine by an angle.
    AboutAxis { angle: f64 },
    /// A root moved rigidly.
    Rigid,
}

/// What the op is, kept to check its own effect afterwards.
#[derive(Clone, Debug)]
pub enum Made {
    Bend(GcBend),
    Resize(GcResize),
    Shift(GcShift),
    Twist(GcTwist),
    Replace(GcReplaceSection),
    Delete(GcDeleteSection),
    Insert(GcInsertSection),
    Shape(GcSetShape),
    Spine(GcReplaceSpine),
    /// The op, how it moves, and where the anchor is dropped.
    Slide(GcTransformPart, Motion, DVec3),
    /// The op, its source part, how it moves, and where it is dropped.
    Copy(GcCopy, usize, Motion, DVec3),
}

impl Made {
    pub fn name(&self) -> &'static str {
        match self {
            Made::Bend(_) => "bend",
            Made::Resize(_) => "resize",
            Made::Shift(_) => "shift",
            Made::Twist(_) => "twist",
            Made::Replace(_) => "replace_section",
            Made::Delete(_) => "delete_section",
            Made::Insert(_) => "insert_section",
            Made::Shape(_) => "set_shape",
            Made::Spine(_) => "replace_spine",
            Made::Slide(..) => "transform_part",
            Made::Copy(..) => "copy",
        }
    }
}

/// The parent's spine as a line (point, unit direction) when it is
/// straight.
pub fn straight_axis(gc: &Gc) -> Option<(DVec3, DVec3)> {
    let c = spine_controls(gc);
    let (a, b) = (*c.first()?, *c.last()?);
    let d = (b - a).try_normalize()?;
    let tol = 1e-9 * spine_size(gc);
    c.iter()
        .all(|p| (*p - a).reject_from_normalized(d).length() <= tol)
        .then_some((a, d))
}

/// The rigid motion (rotation quaternion, translation) a child `c` of
/// `asm` is moved by, and where its anchor is dropped: a slide of about
/// `dist` in a direction of the tangent plane with a spin about the normal,
/// or a turn about the parent's straight spine (a slide when it is not).
pub fn child_motion(
    asm: &GcAssembly,
    c: usize,
    dist: f64,
    s: &Seed,
) -> Option<(Motion, [f64; 4], DVec3, DVec3)> {
    let p = asm.parts[c].parent?;
    let att = asm.parts[c].attach?;
    let parent = &asm.parts[p].gc;
    let surf = parent.surface().ok()?;
    let f = anchor_frame(parent, &surf, att.start).ok()?;
    let anchor = surf.point(att.start.u, att.start.v);
    if s.w < 0.35 {
        if let Some((o, d)) = straight_axis(parent) {
            let angle = std::f64::consts::PI * s.y;
            let q = DQuat::from_axis_angle(d, angle);
            let translate = o - q * o;
            let target = q * anchor + translate;
            return Some((Motion::AboutAxis { angle }, q.to_array(), translate, target));
        }
    }
    // Any direction in the tangent plane (the frame's y axis at `section`
    // 0): a slide along a parallel of a body of revolution, or across a
    // body whose sections are no longer circles, turns the anchor frames
    // about the normal, and only there does following them differ from
    // the least rotation (issue 33's spun copy).
    let (sin, cos) = (std::f64::consts::TAU * s.section).fsin_cos();
    let along = f.matrix3.y_axis * cos + f.matrix3.z_axis * sin;
    let target = project_to_surface(&surf, anchor + along * dist).point;
    // A spin in a quarter of the slides (a plain slide in the rest).
    let spin = if s.w > 0.75 { 0.6 * s.y } else { 0.0 };
    let q = DQuat::from_axis_angle(f.matrix3.x_axis, spin);
    Some((
        Motion::Slide { spin },
        q.to_array(),
        target - q * anchor,
        target,
    ))
}

pub fn make(asm: &GcAssembly, s: &Seed) -> Made {
    let n = asm.parts.len();
    let part = pick(s.part, 0, n);
    let id = PartId(part);
    let gc = &asm.parts[part].gc;
    let k = gc.sections.len();
    let size = spine_size(gc).max(1e-3);
    let child = asm.parts[part].parent.is_some();
    let handle = asm.parts[part].attach.is_some_and(|a| a.end.is_some());
    let mut kind = s.kind;
    // Sections a part can lose, shift or twist are interior ones.
    if matches!(kind, 2 | 3 | 5) && k < 3 {
        kind = 6;
    }
    if kind == 10 && !child {
        kind = 9;
    }
    match kind {
        0 => {
            // Bend in the spine plane; a child keeps its start on the
            // parent (and a handle its end).
            let lo = usize::from(child);
            let hi = if handle { k - 1 } else { k };
            if lo >= hi {
                return make(
                    asm,
                    &Seed {
                        kind: 1,
                        ..s.clone()
                    },
                );
            }
            let i = pick(s.section, lo, hi);
            let key = gc.key_points()[i];
            let t = gc.spine.curve.tangent(gc.sections[i].v).normalize();
            let m = gc.spine.plane_normal.normalize().cross(t);
            Made::Bend(GcBend {
                part: id,
                section: SectionIndex(i),
                to: key + (t * s.x * 0.05 + m * s.y * 0.1) * size,
            })
        }
        1 => Made::Resize(GcResize {
            part: id,
            section: SectionIndex(pick(s.section, 0, k)),
            // 0.5 to 2, as often below 1 as above
            factor: 0.5 * 4f64.fpowf(s.z),
        }),
        2 => {
            let i = pick(s.section, 1, k - 1);
            let (lo, hi) = (gc.sections[i - 1].v, gc.sections[i + 1].v);
            Made::Shift(GcShift {
                part: id,
                section: SectionIndex(i),
                v: lo + (hi - lo) * (0.2 + 0.6 * s.z),
            })
        }
        3 => Made::Twist(GcTwist {
            part: id,
            section: SectionIndex(pick(s.section, 1, k - 1)),
            angle: 0.5 * s.x,
        }),
        4 => {
            let i = pick(s.section, 0, k);
            let sec = &gc.sections[i];
            let r = profile_radius(&sec.profile) * sec.scale * (0.85 + 0.3 * s.z);
            Made::Replace(GcReplaceSection {
                part: id,
                section: SectionIndex(i),
                profile: profile_of_kind(pick(s.w, 0, 6), &sec.profile, r, s.y),
                twist: 0.0,
            })
        }
        5 => Made::Delete(GcDeleteSection {
            part: id,
            section: SectionIndex(pick(s.section, 1, k - 1)),
        }),
        6 => {
            let i = pick(s.section, 0, k - 1);
            let (lo, hi) = (gc.sections[i].v, gc.sections[i + 1].v);
            Made::Insert(GcInsertSection {
                part: id,
                v: lo + (hi - lo) * (0.2 + 0.6 * s.z),
            })
        }
        7 => {
            let f = 0.8 + 0.2 * s.z;
            let shape = match gc.shape {
                ShapeType::Solid => ShapeType::Solid,
                ShapeType::Shell { thickness } => ShapeType::Shell {
                    thickness: thickness * f,
                },
                ShapeType::Container {
                    thickness,
                    closed_end,
                } => ShapeType::Container {
                    thickness: thickness * f,
                    closed_end,
                },
            };
            Made::Shape(GcSetShape { part: id, shape })
        }
        8 => {
            // A new spine through the key points moved in the spine plane
            // (a child keeps its start, a handle its end).
            let nrm = gc.spine.plane_normal.normalize();
            let keys = gc.key_points();
            let kk = keys.len();
            let points = keys
                .iter()
                .enumerate()
                .map(|(j, q)| {
                    if (child && j == 0) || (handle && j + 1 == kk) {
                        return *q;
                    }
                    let t = gc.spine.curve.tangent(gc.sections[j].v).normalize();
                    let m = nrm.cross(t);
                    let w = (j as f64 + 1.0) / kk as f64;
                    *q + m * (s.x * 0.06 * size * w) + t * (s.y * 0.02 * size)
                })
                .collect();
            Made::Spine(GcReplaceSpine {
                part: id,
                points,
                plane_normal: nrm,
            })
        }
        9 => {
            if let Some((motion, rotate, translate, target)) =
                child_motion(asm, part, s.x * 0.15 * size, s)
            {
                Made::Slide(
                    GcTransformPart {
                        part: id,
                        translate,
                        rotate,
                        tolerance: 1e-6,
                    },
                    motion,
                    target,
                )
            } else {
                let axis = DVec3::new(s.x, s.y, 1.0).normalize();
                let q = DQuat::from_axis_angle(axis, s.z);
                let translate = DVec3::new(s.x, s.y, s.z) * 0.1;
                Made::Slide(
                    GcTransformPart {
                        part: id,
                        translate,
                        rotate: q.to_array(),
                        tolerance: 1e-6,
                    },
                    Motion::Rigid,
                    translate,
                )
            }
        }
        _ => {
            // A root's copy is slid along a world axis by up to half its
            // spine's size: its faces stay in the planes of the original's
            // (a table and its copy slid across, the tops' end caps in one
            // plane; issue 33's degenerate triangles).
            let slide = DVec3::AXES[pick(s.y, 0, 3)] * (s.x * 0.5 * size);
            let (motion, rotate, translate, target) = child_motion(asm, part, s.x * 0.15 * size, s)
                .unwrap_or((Motion::Rigid, [0.0, 0.0, 0.0, 1.0], slide, slide));
            Made::Copy(
                GcCopy {
                    part: id,
                    // Mirrored copies are never turned (the tools mirror
                    // in place, then the copy is dragged).
                    mirror: s.z < 0.2 && motion == Motion::Slide { spin: 0.0 },
                    translate,
                    rotate,
                    tolerance: 1e-6,
                },
                part,
                motion,
                target,
            )
        }
    }
}

pub fn apply(asm: &mut GcAssembly, m: &Made) -> Result<(), AssemblyError> {
    match m {
        Made::Bend(e) => propagate_edit(asm, e),
        Made::Resize(e) => propagate_edit(asm, e),
        Made::Shift(e) => propagate_edit(asm, e),
        Made::Twist(e) => propagate_edit(asm, e),
        Made::Replace(e) => propagate_edit(asm, e),
        Made::Delete(e) => propagate_edit(asm, e),
        Made::Insert(e) => propagate_edit(asm, e),
        Made::Shape(e) => propagate_edit(asm, e),
        Made::Spine(e) => propagate_edit(asm, e),
        Made::Slide(e, ..) => e.apply_to(asm),
        Made::Copy(e, ..) => e.apply_to(asm),
    }
}
