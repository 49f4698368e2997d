//! Structure-aware editing (issue 18, paper 1 §3.3) under random edit
//! sequences on the example assemblies (mug, teapot, chair, rack).
//!
//! Every GC edit (bend, resize, shift, twist, replace section, delete,
//! insert, set shape, replace spine), slides (`gc_transform_part`) and
//! copies (`gc_copy`) go through the same functions the document calls.
//! After every op:
//! - each child is still where it sat on its parent: its spine start (and
//!   a handle's end) has the same coordinates in its anchor frame as
//!   before, to 1e-9 of the scene size, unless the op edited that part's
//!   own spine; and the start is within its section's radius of the
//!   anchor point;
//! - each recorded twin pair is mirrored about the parent's spine plane
//!   (control points to 1e-9 of the size, sections' parameters, scales
//!   and negated twists);
//! - each recorded coplanar pair is coplanar, each concentric pair on one
//!   line, and no recorded relation was dropped;
//! - the op did what it says (resize multiplies the scale by the factor,
//!   shift puts the section at `v`, bend puts the key point at `to`, a
//!   slide puts the anchor where it was dropped, ...).
//!
//! Refused ops must be typed errors; the refusal rate is printed and must
//! stay under 10% (inputs are generated the way the tools make them: bends
//! in the spine plane, slides along the parent's surface, replacements by
//! a profile of the same kind).
//! `PROPTEST_CASES` (default 500) sets the number of cases per example.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use glam::{DQuat, DVec3};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use shapewright::assembly::{
    anchor_frame, mirror_plane, project_to_surface, propagate_edit, reflect, spine_controls,
    spine_size, AssemblyError, GcCopy, GcTransformPart,
};
use shapewright::doc::{parse_script, run_script, ObjectId, ObjectKind, OpLog};
use shapewright::gc::*;
use shapewright::nurbs::euclidean;

const EXAMPLES: [&str; 4] = ["mug", "teapot", "chair", "rack"];

fn examples() -> &'static Vec<GcAssembly> {
    static CELL: OnceLock<Vec<GcAssembly>> = OnceLock::new();
    CELL.get_or_init(|| {
        EXAMPLES
            .iter()
            .map(|name| {
                let path = format!("{}/../tests/data/{name}.jsonl", env!("CARGO_MANIFEST_DIR"));
                let text = std::fs::read_to_string(&path).expect("example script");
                let mut log = OpLog::new();
                run_script(&mut log, &parse_script(&text).expect("parses")).expect("runs");
                match &log.document().get(ObjectId(1)).expect("object 1").kind {
                    ObjectKind::GcAssembly(a) => a.clone(),
                    _ => panic!("{name}: not an assembly"),
                }
            })
            .collect()
    })
}

fn scene_size(asm: &GcAssembly) -> f64 {
    asm.parts
        .iter()
        .map(|p| spine_size(&p.gc))
        .fold(0.1, f64::max)
}

fn ends(gc: &Gc) -> (DVec3, DVec3) {
    let (a, b) = gc.spine.curve.domain();
    (gc.spine.curve.point(a), gc.spine.curve.point(b))
}

fn radius(gc: &Gc, first: bool) -> f64 {
    let s = if first {
        &gc.sections[0]
    } else {
        gc.sections.last().expect("sections")
    };
    let c = s.profile.curve().expect("profile");
    c.control
        .iter()
        .map(|h| euclidean(*h).truncate().length())
        .fold(0.0, f64::max)
        * s.scale
}

/// A child's spine start (and a handle's end) in its anchors' frames.
type Local = (DVec3, Option<DVec3>);

fn local_ends(asm: &GcAssembly, c: usize) -> Option<Local> {
    let p = asm.parts[c].parent?;
    let att = asm.parts[c].attach?;
    let parent = &asm.parts[p].gc;
    let surf = parent.surface().expect("parent surface");
    let (s, e) = ends(&asm.parts[c].gc);
    let f0 = anchor_frame(parent, &surf, att.start).expect("frame");
    let start = f0.inverse().transform_point3(s);
    let end = att.end.map(|a| {
        anchor_frame(parent, &surf, a)
            .expect("frame")
            .inverse()
            .transform_point3(e)
    });
    Some((start, end))
}

fn all_local(asm: &GcAssembly) -> Vec<Option<Local>> {
    (0..asm.parts.len()).map(|c| local_ends(asm, c)).collect()
}

fn twins(asm: &GcAssembly, part: usize) -> Vec<usize> {
    asm.relations
        .as_ref()
        .map(|r| r.twins_of(part))
        .unwrap_or_default()
}

/// Checks every relation independently of the core's own check.
fn check_relations(asm: &GcAssembly, expected: &[Option<Local>]) -> Result<(), String> {
    let tol = 1e-9 * scene_size(asm);
    for c in 0..asm.parts.len() {
        let (Some(p), Some(att)) = (asm.parts[c].parent, asm.parts[c].attach) else {
            continue;
        };
        let surf = asm.parts[p].gc.surface().map_err(|e| e.to_string())?;
        let (s, _) = ends(&asm.parts[c].gc);
        let d = surf.point(att.start.u, att.start.v).distance(s);
        if d > radius(&asm.parts[c].gc, true) + tol {
            return Err(format!("part {c} starts {d} from its anchor on {p}"));
        }
        let (Some(now), Some(Some(want))) = (local_ends(asm, c), expected.get(c)) else {
            return Err(format!("part {c}: no expected anchor coordinates"));
        };
        let ds = (now.0 - want.0).length();
        if ds > tol {
            return Err(format!("part {c} start drifted {ds} on its parent {p}"));
        }
        if let (Some(a), Some(b)) = (now.1, want.1) {
            let de = (a - b).length();
            if de > tol {
                return Err(format!("part {c} end drifted {de} on its parent {p}"));
            }
        }
    }
    let Some(rec) = &asm.relations else {
        return Err("no relations recorded".into());
    };
    for &(a, b) in &rec.symmetric {
        let p = asm.parts[a].parent.ok_or("a twin without a parent")?;
        if asm.parts[b].parent != Some(p) {
            return Err(format!("twins {a}, {b} have different parents"));
        }
        let (o, n) = mirror_plane(&asm.parts[p].gc);
        let (ga, gb) = (&asm.parts[a].gc, &asm.parts[b].gc);
        let t = 1e-9 * spine_size(ga).max(spine_size(gb));
        let (ca, cb) = (spine_controls(ga), spine_controls(gb));
        if ca.len() != cb.len() {
            return Err(format!("twins {a}, {b}: spines differ"));
        }
        for (x, y) in ca.iter().zip(&cb) {
            let d = reflect(*x, o, n).distance(*y);
            if d > t {
                return Err(format!(
                    "twins {a}, {b}: control point off the mirror by {d}"
                ));
            }
        }
        if ga.sections.len() != gb.sections.len() {
            return Err(format!("twins {a}, {b}: section counts differ"));
        }
        for (x, y) in ga.sections.iter().zip(&gb.sections) {
            if (x.v - y.v).abs() > 1e-12
                || (x.scale - y.scale).abs() > 1e-12 * x.scale
                || (x.twist + y.twist).abs() > 1e-12
            {
                return Err(format!("twins {a}, {b}: sections not mirrored"));
            }
        }
        if ga.shape != gb.shape {
            return Err(format!("twins {a}, {b}: shapes differ"));
        }
    }
    for &(a, b) in &rec.coplanar {
        let (ga, gb) = (&asm.parts[a].gc, &asm.parts[b].gc);
        let t = 1e-9 * spine_size(ga).max(spine_size(gb));
        let n = ga.spine.plane_normal.normalize();
        let o = spine_controls(ga)[0];
        if n.dot(gb.spine.plane_normal.normalize()).abs() < 1.0 - 1e-9 {
            return Err(format!("coplanar {a}, {b}: planes turned apart"));
        }
        for q in spine_controls(gb) {
            let d = (q - o).dot(n).abs();
            if d > t {
                return Err(format!(
                    "coplanar {a}, {b}: a spine point {d} off the plane"
                ));
            }
        }
    }
    for &(a, b) in &rec.concentric {
        let (ca, cb) = (
            spine_controls(&asm.parts[a].gc),
            spine_controls(&asm.parts[b].gc),
        );
        let t = 1e-9 * scene_size(asm);
        let dir = (ca[ca.len() - 1] - ca[0]).normalize();
        for q in ca.iter().chain(&cb) {
            let d = (*q - ca[0]).reject_from_normalized(dir).length();
            if d > t {
                return Err(format!(
                    "concentric {a}, {b}: a spine point {d} off the axis"
                ));
            }
        }
    }
    Ok(())
}

/// The random numbers one op is made from (read against the assembly as
/// it is when the op is made).
#[derive(Clone, Debug)]
struct Seed {
    kind: u8,
    part: f64,
    section: f64,
    x: f64,
    y: f64,
    z: f64,
}

fn seed() -> impl Strategy<Value = Seed> {
    (
        0u8..11,
        0.0..1.0f64,
        0.0..1.0f64,
        -1.0..1.0f64,
        -1.0..1.0f64,
        0.0..1.0f64,
    )
        .prop_map(|(kind, part, section, x, y, z)| Seed {
            kind,
            part,
            section,
            x,
            y,
            z,
        })
}

fn pick(x: f64, lo: usize, hi: usize) -> usize {
    (lo + (x * (hi - lo) as f64) as usize).min(hi - 1)
}

fn scaled(p: &Profile, f: f64, g: f64) -> Profile {
    match p {
        Profile::Circle { radius } => Profile::Circle { radius: radius * f },
        Profile::Ellipse { rx, ry } => Profile::Ellipse {
            rx: rx * f,
            ry: ry * g,
        },
        Profile::Rectangle { width, height } => Profile::Rectangle {
            width: width * f,
            height: height * g,
        },
        Profile::Polygon { sides, radius } => Profile::Polygon {
            sides: *sides,
            radius: radius * f,
        },
        other => other.clone(),
    }
}

/// What the op is, kept to check its own effect afterwards.
#[derive(Clone, Debug)]
enum Made {
    Bend(GcBend),
    Resize(GcResize),
    Shift(GcShift),
    Twist(GcTwist),
    Replace(GcReplaceSection),
    Delete(GcDeleteSection),
    Insert(GcInsertSection),
    Shape(GcSetShape),
    Spine(GcReplaceSpine),
    Slide(GcTransformPart, DVec3),
    Copy(GcCopy, usize),
}

impl Made {
    fn name(&self) -> &'static str {
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

/// A slide of child `c` along its parent's surface by about `dist` in
/// the direction of the parent's spine: the translation the GC tool
/// sends (the dragged anchor projected back on the surface).
fn slide_translation(asm: &GcAssembly, c: usize, dist: f64) -> Option<(DVec3, DVec3)> {
    let p = asm.parts[c].parent?;
    let att = asm.parts[c].attach?;
    let parent = &asm.parts[p].gc;
    let surf = parent.surface().ok()?;
    let f = anchor_frame(parent, &surf, att.start).ok()?;
    let anchor = surf.point(att.start.u, att.start.v);
    let target = project_to_surface(&surf, anchor + f.matrix3.y_axis * dist).point;
    Some((target - anchor, target))
}

fn make(asm: &GcAssembly, s: &Seed) -> Made {
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
            factor: 0.8 + 0.45 * s.z,
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
            Made::Replace(GcReplaceSection {
                part: id,
                section: SectionIndex(i),
                profile: scaled(
                    &gc.sections[i].profile,
                    0.85 + 0.3 * s.z,
                    0.9 + 0.1 * s.y.abs(),
                ),
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
            if let Some((translate, target)) = slide_translation(asm, part, s.x * 0.15 * size) {
                Made::Slide(
                    GcTransformPart {
                        part: id,
                        translate,
                        rotate: [0.0, 0.0, 0.0, 1.0],
                        tolerance: 1e-6,
                    },
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
                    translate,
                )
            }
        }
        _ => {
            let (translate, _) = slide_translation(asm, part, s.x * 0.15 * size)
                .unwrap_or((DVec3::ZERO, DVec3::ZERO));
            Made::Copy(
                GcCopy {
                    part: id,
                    mirror: s.z < 0.25,
                    translate,
                    rotate: [0.0, 0.0, 0.0, 1.0],
                    tolerance: 1e-6,
                },
                part,
            )
        }
    }
}

fn apply(asm: &mut GcAssembly, m: &Made) -> Result<(), AssemblyError> {
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
        Made::Slide(e, _) => e.apply_to(asm),
        Made::Copy(e, _) => e.apply_to(asm),
    }
}

/// The parts whose own spine the op edited (their anchor coordinates may
/// change; every other child's must not).
fn own_spine_edited(before: &GcAssembly, m: &Made) -> Vec<usize> {
    let part = match m {
        Made::Bend(e) => e.part.0,
        Made::Spine(e) => e.part.0,
        _ => return Vec::new(),
    };
    let mut v = vec![part];
    v.extend(twins(before, part));
    v
}

/// Checks that the op did what it says, on the part and its twins.
fn check_effect(before: &GcAssembly, after: &GcAssembly, m: &Made) -> Result<(), String> {
    let tol = 1e-9 * scene_size(before);
    let with_twins = |p: usize| {
        let mut v = vec![p];
        v.extend(twins(before, p));
        v
    };
    match m {
        Made::Bend(e) => {
            let got = after.parts[e.part.0].gc.key_points()[e.section.0];
            let d = got.distance(e.to);
            if d > tol {
                return Err(format!("bend: key point {d} from its target"));
            }
        }
        Made::Resize(e) => {
            for p in with_twins(e.part.0) {
                let (a, b) = (
                    before.parts[p].gc.sections[e.section.0].scale,
                    after.parts[p].gc.sections[e.section.0].scale,
                );
                if b != a * e.factor {
                    return Err(format!(
                        "resize part {p}: scale {a} -> {b}, factor {}",
                        e.factor
                    ));
                }
            }
        }
        Made::Shift(e) => {
            for p in with_twins(e.part.0) {
                let g = &after.parts[p].gc;
                if g.sections[e.section.0].v != e.v {
                    return Err(format!("shift part {p}: section not at v = {}", e.v));
                }
                // it moved along the (unchanged) spine by the arc between
                let (a0, a1) = (
                    before.parts[p].gc.key_points()[e.section.0],
                    g.key_points()[e.section.0],
                );
                let want = g.spine.curve.point(e.v);
                if a1.distance(want) > tol
                    || (a0 == a1 && before.parts[p].gc.sections[e.section.0].v != e.v)
                {
                    return Err(format!("shift part {p}: key point not on the spine at v"));
                }
            }
        }
        Made::Twist(e) => {
            for (j, p) in with_twins(e.part.0).into_iter().enumerate() {
                let sign = if j == 0 { 1.0 } else { -1.0 };
                let (a, b) = (
                    before.parts[p].gc.sections[e.section.0].twist,
                    after.parts[p].gc.sections[e.section.0].twist,
                );
                if ((b - a) - sign * e.angle).abs() > 1e-12 {
                    return Err(format!("twist part {p}: {a} -> {b}, angle {}", e.angle));
                }
            }
        }
        Made::Replace(e) => {
            let s = &after.parts[e.part.0].gc.sections[e.section.0];
            if s.profile != e.profile || s.scale != 1.0 || s.twist != 0.0 {
                return Err("replace: section is not the new profile".into());
            }
        }
        Made::Delete(e) => {
            for p in with_twins(e.part.0) {
                let (b, a) = (&before.parts[p].gc.sections, &after.parts[p].gc.sections);
                let mut want = b.clone();
                want.remove(e.section.0);
                if *a != want {
                    return Err(format!("delete part {p}: sections are not the others"));
                }
            }
        }
        Made::Insert(e) => {
            for p in with_twins(e.part.0) {
                let (b, a) = (&before.parts[p].gc, &after.parts[p].gc);
                if a.sections.len() != b.sections.len() + 1
                    || !a.sections.iter().any(|s| s.v == e.v)
                {
                    return Err(format!("insert part {p}: no section at v = {}", e.v));
                }
                // the surface is unchanged: sample it
                let (sa, sb) = (
                    a.surface().map_err(|e| e.to_string())?,
                    b.surface().map_err(|e| e.to_string())?,
                );
                let ((u0, u1), (v0, v1)) = sb.domain();
                for i in 0..5 {
                    for j in 0..5 {
                        let (u, v) = (
                            u0 + (u1 - u0) * i as f64 / 5.0,
                            v0 + (v1 - v0) * j as f64 / 4.0,
                        );
                        let d = sa.point(u, v).distance(sb.point(u, v));
                        if d > tol {
                            return Err(format!("insert part {p}: surface moved {d}"));
                        }
                    }
                }
            }
        }
        Made::Shape(e) => {
            for p in with_twins(e.part.0) {
                if after.parts[p].gc.shape != e.shape {
                    return Err(format!("set_shape part {p}: shape not set"));
                }
            }
        }
        Made::Spine(e) => {
            let g = &after.parts[e.part.0].gc;
            let (s, t) = ends(g);
            let (d0, d1) = (
                s.distance(e.points[0]),
                t.distance(*e.points.last().expect("points")),
            );
            if d0 > tol || d1 > tol {
                return Err(format!(
                    "replace_spine: ends {d0}, {d1} from the new points"
                ));
            }
        }
        Made::Slide(e, target) => {
            let p = e.part.0;
            match (after.parts[p].parent, after.parts[p].attach) {
                (Some(par), Some(att)) => {
                    let surf = after.parts[par].gc.surface().map_err(|e| e.to_string())?;
                    let d = surf.point(att.start.u, att.start.v).distance(*target);
                    if d > tol {
                        return Err(format!("slide: anchor {d} from where it was dropped"));
                    }
                }
                _ => {
                    let q = DQuat::from_array(e.rotate).normalize();
                    let want = q * ends(&before.parts[p].gc).0 + e.translate;
                    let d = ends(&after.parts[p].gc).0.distance(want);
                    if d > tol {
                        return Err(format!("root move: start {d} from where it should be"));
                    }
                }
            }
        }
        Made::Copy(e, src) => {
            let k = before.parts.len();
            if after.parts.len() <= k {
                return Err("copy: no part added".into());
            }
            if after.parts[k].parent != before.parts[*src].parent {
                return Err("copy: not on the source's parent".into());
            }
            if !e.mirror && twins(after, *src).contains(&k) {
                return Err("copy: an unmirrored copy was taken for its source's twin".into());
            }
            if !e.mirror {
                // placed where dropped: the source's anchor coordinates at
                // the slid anchor
                let (a, b) = (local_ends(before, *src), local_ends(after, k));
                if let (Some(a), Some(b)) = (a, b) {
                    let d = (a.0 - b.0).length();
                    if d > tol {
                        return Err(format!(
                            "copy: start {d} off the source's anchor coordinates"
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

#[derive(Default)]
struct Stats {
    ops: usize,
    refused: usize,
    reasons: BTreeMap<String, usize>,
}

fn run_case(ex: usize, seeds: &[Seed], stats: &mut Stats) -> Result<(), TestCaseError> {
    let mut asm = examples()[ex].clone();
    let mut expected = all_local(&asm);
    let mut recorded = asm.relations.clone().expect("examples record relations");
    for s in seeds {
        let m = make(&asm, s);
        let mut next = asm.clone();
        stats.ops += 1;
        match apply(&mut next, &m) {
            Err(e) => {
                stats.refused += 1;
                let key = format!(
                    "{}: {}",
                    m.name(),
                    format!("{e:?}").split(['{', '(']).next().unwrap_or("")
                );
                let key = match &e {
                    AssemblyError::RelationBroken { relation, .. } => {
                        format!("{}: broken {relation}", m.name())
                    }
                    AssemblyError::Gc(g) => format!(
                        "{}: {}",
                        m.name(),
                        format!("{g:?}").split(['{', '(', ' ']).next().unwrap_or("")
                    ),
                    _ => key,
                };
                *stats.reasons.entry(key).or_default() += 1;
                prop_assert!(
                    matches!(
                        e,
                        AssemblyError::RelationBroken { .. }
                            | AssemblyError::OffSurface { .. }
                            | AssemblyError::Gc(_)
                    ),
                    "untyped refusal {e:?}"
                );
            }
            Ok(()) => {
                check_effect(&asm, &next, &m)
                    .map_err(|e| TestCaseError::fail(format!("{m:?}: {e}")))?;
                for p in own_spine_edited(&asm, &m) {
                    expected[p] = local_ends(&next, p);
                }
                expected.resize(next.parts.len(), None);
                for (c, e) in expected.iter_mut().enumerate() {
                    if e.is_none() {
                        *e = local_ends(&next, c);
                    }
                }
                check_relations(&next, &expected)
                    .map_err(|e| TestCaseError::fail(format!("after {m:?}: {e}")))?;
                let rec = next.relations.clone().expect("recorded");
                for (old, new) in [
                    (&recorded.symmetric, &rec.symmetric),
                    (&recorded.coplanar, &rec.coplanar),
                    (&recorded.concentric, &rec.concentric),
                ] {
                    prop_assert!(
                        old.iter().all(|p| new.contains(p)),
                        "a relation was dropped by {m:?}"
                    );
                }
                recorded = rec;
                asm = next;
            }
        }
    }
    Ok(())
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(500)
}

fn run_example(ex: usize) {
    let mut runner = TestRunner::new(Config {
        cases: cases(),
        failure_persistence: None,
        ..Config::default()
    });
    let stats = std::cell::RefCell::new(Stats::default());
    let result = runner.run(&prop::collection::vec(seed(), 1..7), |seeds| {
        run_case(ex, &seeds, &mut stats.borrow_mut())
    });
    if let Err(e) = result {
        panic!("{}: {e}", EXAMPLES[ex]);
    }
    let s = stats.borrow();
    let rate = s.refused as f64 / s.ops.max(1) as f64;
    eprintln!(
        "{}: {} cases, {} ops, {} refused ({:.1}%), 0 broken relations; refusals: {:?}",
        EXAMPLES[ex],
        cases(),
        s.ops,
        s.refused,
        100.0 * rate,
        s.reasons
    );
    assert!(
        rate < 0.10,
        "{}: {:.1}% of ops refused",
        EXAMPLES[ex],
        100.0 * rate
    );
}

#[test]
fn the_examples_record_their_relations() {
    let ex = examples();
    let rec = |i: usize| ex[i].relations.clone().expect("recorded");
    // mug: the handle is in the body's spine plane
    assert!(rec(0).coplanar.contains(&(0, 1)), "{:?}", rec(0));
    // teapot: spout and handle coplanar (for pouring), with the body
    for p in [(0, 1), (0, 2), (1, 2)] {
        assert!(rec(1).coplanar.contains(&p), "{:?}", rec(1));
    }
    // chair: three mirrored pairs (front legs, back legs, back posts)
    for p in [(1, 2), (3, 4), (5, 6)] {
        assert!(rec(2).symmetric.contains(&p), "{:?}", rec(2));
    }
    // rack: the mirrored feet
    assert!(rec(3).symmetric.contains(&(3, 4)), "{:?}", rec(3));
    assert!(rec(3).symmetric.contains(&(5, 6)), "{:?}", rec(3));
}

#[test]
fn mug_random_edits_keep_relations() {
    run_example(0);
}

#[test]
fn teapot_random_edits_keep_relations() {
    run_example(1);
}

#[test]
fn chair_random_edits_keep_relations() {
    run_example(2);
}

#[test]
fn rack_random_edits_keep_relations() {
    run_example(3);
}
