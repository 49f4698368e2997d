//! Creating a part (paper §4, Figure 12) and replacing a spine or a
//! section by sketching: the sketch planes, and the ops a finished stroke
//! becomes.
//!
//! - A child starts at a point `O_s` picked on a part: its section is
//!   sketched in the plane tangent to the parent there (normal `n_s`), its
//!   spine in the plane through `O_s` with normal `n_s x t_s`. A root
//!   starts at an empty-space point: section on the ground plane, spine
//!   in the vertical plane facing the user.
//! - The spine stroke is simplified by RDP and translated so it starts at
//!   `O_s`; a child's spine is then sunk into its parent by 0.6 of the
//!   section's radius, so the start cap is inside the parent and the
//!   union is one solid (a section placed exactly on a curved surface
//!   would leave a sliver gap). A child whose stroke ends within
//!   [`super::GcToolSettings::land_distance`] of the parent lands on it
//!   (a handle), else its end is free (a spout).
//! - Key sections: the matched section template, at evenly spaced
//!   parameters, one per [`super::GcToolSettings::section_spacing`] of
//!   spine length (3 to [`super::GcToolSettings::sections`]), turned
//!   (twisted) so the first lies as it was drawn: an ellipse drawn
//!   diagonally stays diagonal (a drawn loop is mapped into the section's
//!   frame point by point). A replacing section keeps its drawn turn too.
//! - The spine is the cubic through the stroke's RDP points, with stroke
//!   samples added where it strays farther than the spine tolerance from
//!   the stroke ([`spine_points`], as the Blender sketch does).

use crate::assembly::{anchor_frame, project_to_surface, ChildEnd, GcAddChild};
use crate::doc::{Create, Edit, ObjectId, Op};
use crate::gc::{
    fit_spine, GcAssembly, GcCreate, GcReplaceSection, GcReplaceSpine, PartId, Profile,
    SectionIndex, SectionSpec, ShapeType, SpineFrames,
};
use crate::math::DVec3;
use crate::sketch::{match_section_stroke, spine_points, DrawnSection, SketchPlane};

use super::target::GeoCache;
use super::GcTarget;
use super::GcToolSettings;

/// Where a new part starts.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Start {
    /// The parent object and part (`None`: a new root).
    pub parent: Option<(ObjectId, usize)>,
    /// `O_s` (model space).
    pub point: DVec3,
    /// The plane the section is sketched in.
    pub section_plane: SketchPlane,
    /// The plane the spine is sketched in (for a child, coordinates
    /// `(n_s, t_s)` about `O_s`).
    pub spine_plane: SketchPlane,
}

impl Start {
    /// The start at `target` (a surface point or empty space), with the
    /// user looking along `view_dir` (model space).
    pub fn at(target: &GcTarget, view_dir: DVec3, geo: &GeoCache) -> Option<Start> {
        match *target {
            GcTarget::Surface {
                id, part, point, ..
            } => {
                let asm = geo.assembly(id)?;
                let pg = geo.part(id, part)?;
                let proj = project_to_surface(&pg.surface, point);
                let f = anchor_frame(&asm.parts[part].gc, &pg.surface, proj.anchor).ok()?;
                let (n, t) = (f.matrix3.x_axis, f.matrix3.y_axis);
                let o = proj.point;
                Some(Start {
                    parent: Some((id, part)),
                    point: o,
                    section_plane: SketchPlane::new(o, n, n.cross(t)).ok()?,
                    spine_plane: SketchPlane::new(o, n.cross(t), n).ok()?,
                })
            }
            GcTarget::Empty { point } => {
                let h = DVec3::new(view_dir.x, view_dir.y, 0.0)
                    .try_normalize()
                    .unwrap_or(DVec3::Y);
                Some(Start {
                    parent: None,
                    point,
                    section_plane: SketchPlane::new(point, DVec3::Z, DVec3::X).ok()?,
                    spine_plane: SketchPlane::new(point, h, h.cross(DVec3::Z)).ok()?,
                })
            }
            _ => None,
        }
    }
}

/// The loop of a drawn closed stroke. A drawn loop comes back to (and
/// often past) where it started, and both ends carry small hooks (the
/// fingertip settles while the gesture changes); either would cross the
/// loop. The loop runs between the closest pair of samples `(i, j)` with
/// `i` in the first and `j` in the last quarter of the stroke, `j` left
/// out (it nearly repeats `i`).
fn close_loop(stroke: &[DVec3]) -> &[DVec3] {
    let n = stroke.len();
    if n < 8 {
        return stroke;
    }
    let q = n / 4;
    let mut best = (f64::INFINITY, 0, n);
    for i in 0..=q {
        for j in n - 1 - q..n {
            let d = (stroke[j] - stroke[i]).length();
            if d < best.0 {
                best = (d, i, j);
            }
        }
    }
    &stroke[best.1..best.2]
}

/// The section a closed stroke becomes: the best template, turned as it
/// was drawn, or the loop itself when no template fits well.
pub(super) fn section_profile(
    stroke: &[DVec3],
    plane: &SketchPlane,
    s: &GcToolSettings,
) -> Option<DrawnSection> {
    let m = match_section_stroke(close_loop(stroke), plane).ok()?;
    let d = m.drawn(s.min_template_score);
    d.profile.curve().ok().map(|_| d)
}

/// Largest distance of the profile from its centre.
fn profile_radius(p: &Profile) -> f64 {
    p.curve().map_or(0.0, |c| {
        (0..64)
            .map(|i| c.point(i as f64 / 64.0).truncate().length())
            .fold(0.0, f64::max)
    })
}

fn specs(profile: &Profile, twist: f64, n: usize) -> Vec<SectionSpec> {
    let n = n.max(2);
    (0..n)
        .map(|i| SectionSpec {
            profile: profile.clone(),
            v: i as f64 / (n - 1) as f64,
            scale: 1.0,
            twist,
        })
        .collect()
}

/// `drawn` (sketched in `plane`) as the key sections of a part whose spine
/// interpolates `spine` (world, in the plane with normal `normal`): the
/// section turned in the first section's frame as it was drawn.
fn drawn_sections(
    drawn: &DrawnSection,
    plane: &SketchPlane,
    spine: &[DVec3],
    normal: DVec3,
    n: usize,
) -> Option<Vec<SectionSpec>> {
    let sp = fit_spine(spine, normal).ok()?;
    let frame = SpineFrames::new(&sp)
        .ok()?
        .at(&sp, sp.curve.domain().0)
        .ok()?;
    let (profile, twist) = drawn.in_frame(plane, frame.r, frame.s);
    Some(specs(&profile, twist, n))
}

/// The op that creates the part from its start, section and spine stroke.
pub(super) fn create_op(
    start: &Start,
    drawn: &DrawnSection,
    stroke: &[DVec3],
    geo: &GeoCache,
    s: &GcToolSettings,
) -> Option<Op> {
    let (simplified, _) = spine_points(stroke, &start.spine_plane, s.spine_tolerance).ok()?;
    let first = *simplified.first()?;
    let length: f64 = simplified.windows(2).map(|w| (w[1] - w[0]).length()).sum();
    let count = (1.0 + (length / s.section_spacing).ceil()).clamp(3.0, s.sections.max(3) as f64);
    let Some((id, part)) = start.parent else {
        let spine: Vec<DVec3> = simplified
            .iter()
            .map(|p| *p - first + start.point)
            .collect();
        let normal = start.spine_plane.normal;
        let sections = drawn_sections(drawn, &start.section_plane, &spine, normal, count as usize)?;
        return Some(Op::GcCreate(Create(GcCreate {
            spine,
            plane_normal: normal,
            sections,
            shape: ShapeType::Solid,
            resolution: s.resolution,
        })));
    };
    let plane = &start.spine_plane;
    let depth = 0.6 * profile_radius(&drawn.profile);
    let o = plane.project(first);
    let spine: Vec<[f64; 2]> = simplified
        .iter()
        .map(|p| {
            let q = plane.project(*p) - o;
            [q.x - depth, q.y]
        })
        .collect();
    // `gc_add_child` puts spine point `[a, b]` at `O_s + a n + b t`: the
    // spine plane's lift.
    let world: Vec<DVec3> = spine
        .iter()
        .map(|q| plane.lift(glam::DVec2::new(q[0], q[1])))
        .collect();
    let sections = drawn_sections(
        drawn,
        &start.section_plane,
        &world,
        plane.normal,
        count as usize,
    )?;
    let pg = geo.part(id, part)?;
    let last = spine.last()?;
    let end_raw = plane.lift(glam::DVec2::new(last[0] + depth, last[1]));
    let lands = project_to_surface(&pg.surface, end_raw).distance < s.land_distance;
    let end_sunk = plane.lift(glam::DVec2::new(last[0], last[1]));
    let end_distance = project_to_surface(&pg.surface, end_sunk).distance;
    Some(Op::GcAddChild(Edit::new(
        id,
        GcAddChild {
            parent: PartId(part),
            at: start.point,
            tolerance: 1e-4,
            spine,
            end: if lands {
                ChildEnd::Parent
            } else {
                ChildEnd::Free
            },
            end_tolerance: (end_distance * 1.25).max(1e-4),
            sections,
            shape: ShapeType::Solid,
            resolution: s.resolution,
        },
    )))
}

/// The plane a replacing stroke is sketched in: the spine plane for a key
/// point, the section's plane for a section.
pub(super) fn replace_plane(target: &GcTarget, geo: &GeoCache) -> Option<SketchPlane> {
    match *target {
        GcTarget::KeyPoint {
            id, part, section, ..
        } => {
            let gc = &geo.assembly(id)?.parts.get(part)?.gc;
            let f = geo.part(id, part)?.frames.get(section)?;
            SketchPlane::new(f.origin, gc.spine.plane_normal, f.tangent).ok()
        }
        GcTarget::Section {
            id, part, section, ..
        } => {
            let f = geo.part(id, part)?.frames.get(section)?;
            SketchPlane::new(f.origin, f.tangent, f.r).ok()
        }
        _ => None,
    }
}

/// The op a replacing stroke becomes: a new spine through the simplified
/// stroke, moved to start where the old spine started, or a new profile
/// for the section.
pub(super) fn replace_op(
    target: &GcTarget,
    plane: &SketchPlane,
    stroke: &[DVec3],
    asm: &GcAssembly,
    s: &GcToolSettings,
) -> Option<Op> {
    match *target {
        GcTarget::KeyPoint { id, part, .. } => {
            let gc = &asm.parts.get(part)?.gc;
            let (simplified, _) = spine_points(stroke, plane, s.spine_tolerance).ok()?;
            let start = gc.spine.curve.point(gc.spine.curve.domain().0);
            let first = *simplified.first()?;
            let n = gc.spine.plane_normal;
            let shift = (start - first) - n * (start - first).dot(n);
            Some(Op::GcReplaceSpine(Edit::new(
                id,
                GcReplaceSpine {
                    part: PartId(part),
                    points: simplified.iter().map(|p| *p + shift).collect(),
                    plane_normal: n,
                },
            )))
        }
        GcTarget::Section {
            id, part, section, ..
        } => {
            // The plane's axes are the section frame's `r` and `s`.
            let (profile, twist) =
                section_profile(stroke, plane, s)?.in_frame(plane, plane.x, plane.y);
            Some(Op::GcReplaceSection(Edit::new(
                id,
                GcReplaceSection {
                    part: PartId(part),
                    section: SectionIndex(section),
                    profile,
                    twist,
                },
            )))
        }
        _ => None,
    }
}
