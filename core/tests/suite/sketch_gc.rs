//! Sketched GC edits through the op log (issue 20, "sketches that keep
//! their shape"): a sketched arc gives a tube that follows it, a sketched
//! handle lands on its parent, and a replaced spine keeps its part. The
//! ops are built from `shapewright::sketch` values as JSON, the way the
//! Blender add-on builds them.

use shapewright::math::fm::DetMath as _;
use std::f64::consts::PI;

use serde_json::json;
use shapewright::doc::{ObjectId, ObjectKind, Op, OpLog};
use shapewright::gc::{Gc, GcAssembly};
use shapewright::math::DVec3;
use shapewright::mesh::validate;
use shapewright::sketch::{
    child_from_stroke, profile_radius, replace_spine_from_stroke, sketch_spine, ChildSettings,
    EndChoice, SectionSettings, SketchPlane,
};

fn apply(log: &mut OpLog, v: serde_json::Value) -> Option<ObjectId> {
    let op: Op = serde_json::from_value(v).expect("op parses");
    log.apply(op).expect("op applies").created
}

fn assembly(log: &OpLog, id: ObjectId) -> GcAssembly {
    match &log.document().get(id).unwrap().kind {
        ObjectKind::GcAssembly(a) => a.clone(),
        other => panic!("{}", other.name()),
    }
}

fn sections(radius: f64, params: &[f64]) -> serde_json::Value {
    params
        .iter()
        .map(|v| json!({"profile": {"template": "circle", "radius": radius}, "v": v}))
        .collect()
}

/// Ring centre of the GC's skin at `v`.
fn ring_centre(gc: &Gc, v: f64) -> DVec3 {
    let s = gc.surface().unwrap();
    (0..64).map(|i| s.point(i as f64 / 64.0, v)).sum::<DVec3>() / 64.0
}

/// Distance from `p` to the polyline `stroke`.
fn to_polyline(p: DVec3, stroke: &[DVec3]) -> f64 {
    stroke
        .windows(2)
        .map(|w| {
            let ab = w[1] - w[0];
            let t = ((p - w[0]).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
            (w[0] + ab * t - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// A mouse stroke on the XZ plane (y = 0): a quarter arc of radius
/// 0.12 m, samples 5 mm apart as the add-on's sketch keeps them.
fn arc() -> Vec<DVec3> {
    let n = (0.12 * 0.5 * PI / 0.005) as usize;
    (0..=n)
        .map(|i| {
            let a = 0.5 * PI * i as f64 / n as f64;
            DVec3::new(0.12 * (1.0 - a.fcos()), 0.0, 0.12 * a.fsin())
        })
        .collect()
}

#[test]
fn a_sketched_arc_gives_a_curved_tube_that_follows_the_stroke() {
    let stroke = arc();
    let plane = SketchPlane::new(stroke[0], DVec3::Y, DVec3::X).unwrap();
    let r = 0.02;
    let sk = sketch_spine(&stroke, &plane, r, &SectionSettings::default()).unwrap();
    let mut log = OpLog::new();
    let id = apply(
        &mut log,
        json!({"op": "gc_create", "spine": sk.points, "plane_normal": sk.plane_normal,
               "sections": sections(r, &sk.plan.params)}),
    )
    .unwrap();
    let gc = assembly(&log, id).parts[0].gc.clone();
    // 20 samples along the tube: its axis stays within 2 mm of the stroke.
    let worst = (0..20)
        .map(|i| to_polyline(ring_centre(&gc, i as f64 / 19.0), &stroke))
        .fold(0.0, f64::max);
    assert!(
        worst < 2e-3,
        "the tube's axis strays {worst} m from the sketch"
    );
    let mesh = &log.document().get(id).unwrap().mesh;
    assert!(validate(mesh, &Default::default()).is_closed_manifold());
    // What the two-section tube did: a chord, far from the arc.
    let mut straight = OpLog::new();
    let id2 = apply(
        &mut straight,
        json!({"op": "gc_create", "spine": sk.points, "plane_normal": sk.plane_normal,
               "sections": sections(r, &[0.0, 1.0])}),
    )
    .unwrap();
    let gc2 = assembly(&straight, id2).parts[0].gc.clone();
    let mid = to_polyline(ring_centre(&gc2, 0.5), &stroke);
    assert!(mid > 0.01, "two sections follow the arc within {mid}?");
}

/// A mug body: a vertical cylinder of radius 0.04, 0.1 high, at the origin.
fn body(log: &mut OpLog) -> ObjectId {
    apply(
        log,
        json!({"op": "gc_create", "spine": [[0, 0, 0], [0, 0, 0.1]], "plane_normal": [0, 1, 0],
               "sections": sections(0.04, &[0.0, 1.0])}),
    )
    .unwrap()
}

/// A handle stroke on the XZ plane from the body's side at z = 0.08 out
/// to x = 0.075 and back to the side at z = 0.02.
fn handle_stroke() -> Vec<DVec3> {
    (0..=40)
        .map(|i| {
            let a = PI * i as f64 / 40.0;
            DVec3::new(0.04 + 0.035 * a.fsin(), 0.0, 0.05 + 0.03 * a.fcos())
        })
        .collect()
}

#[test]
fn a_sketched_handle_lands_on_its_parent() {
    let mut log = OpLog::new();
    let id = body(&mut log);
    let before = validate(&log.document().get(id).unwrap().mesh, &Default::default()).signed_volume;
    let profile = json!({"template": "circle", "radius": 0.006});
    let r = profile_radius(&serde_json::from_value(profile.clone()).unwrap());
    assert!((r - 0.006).abs() < 1e-6);
    let asm = assembly(&log, id);
    let c = child_from_stroke(
        &asm,
        &handle_stroke(),
        r,
        EndChoice::Auto,
        &ChildSettings::default(),
    )
    .unwrap();
    assert!(c.lands, "the stroke ends on the body: a handle");
    assert!(c.plan.params.len() > 3, "{:?}", c.plan.params);
    let secs: Vec<_> = c
        .plan
        .params
        .iter()
        .map(|v| json!({"profile": profile, "v": v}))
        .collect();
    apply(
        &mut log,
        json!({"op": "gc_add_child", "id": id.0, "parent": c.parent, "at": c.at, "spine": c.spine,
               "end": "parent", "end_tolerance": c.end_tolerance, "sections": secs}),
    );
    let asm = assembly(&log, id);
    assert_eq!(asm.parts.len(), 2);
    assert!(
        asm.parts[1].attach.unwrap().end.is_some(),
        "the end is anchored"
    );
    let report = validate(&log.document().get(id).unwrap().mesh, &Default::default());
    assert!(report.is_closed_manifold(), "{}", report.problems());
    assert_eq!(report.genus, Some(1), "a handle makes a through hole");
    assert!(report.signed_volume > before);
    // The handle's axis follows the stroke, sunk into the body by 0.6 of
    // its radius along the start's surface normal (+x here) as the
    // headset's tool does, so both ends are inside the body.
    let gc = &asm.parts[1].gc;
    let stroke = handle_stroke();
    let sunk: Vec<DVec3> = stroke.iter().map(|p| *p - DVec3::X * (0.6 * r)).collect();
    for i in 0..20 {
        let d = to_polyline(ring_centre(gc, i as f64 / 19.0), &sunk);
        assert!(d < 2e-3, "handle axis {d} from the stroke at {i}");
    }
    // A stroke that starts in the air is refused with the distance.
    let off: Vec<DVec3> = stroke
        .iter()
        .map(|p| *p + DVec3::new(0.1, 0.0, 0.1))
        .collect();
    let e = child_from_stroke(&asm, &off, r, EndChoice::Auto, &ChildSettings::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("starts") && e.contains("mm"), "{e}");
}

#[test]
fn replacing_a_two_section_handles_spine_keeps_the_part() {
    // A straight two-section spout on the body's side.
    let mut log = OpLog::new();
    let id = body(&mut log);
    apply(
        &mut log,
        json!({"op": "gc_add_child", "id": id.0, "parent": 0, "at": [0.04, 0, 0.05],
               "spine": [[-0.004, 0.0], [0.05, 0.0]], "end": "free",
               "sections": sections(0.006, &[0.0, 1.0])}),
    );
    let one_part = validate(&log.document().get(id).unwrap().mesh, &Default::default());
    // The new spine is sketched on a plane far from the part: it is moved
    // to start where the old one started, and gets the sections it needs.
    let stroke: Vec<DVec3> = (0..=30)
        .map(|i| {
            let a = 0.6 * PI * i as f64 / 30.0;
            DVec3::new(0.5 + 0.05 * a.fsin(), 0.0, 0.3 + 0.05 * (1.0 - a.fcos()))
        })
        .collect();
    let asm = assembly(&log, id);
    let rep = replace_spine_from_stroke(&asm, 1, &stroke, &SectionSettings::default()).unwrap();
    assert!(!rep.insert_at.is_empty());
    let old_start = asm.parts[1].gc.spine.curve.point(0.0);
    assert!((rep.points[0] - old_start).length() < 1e-9);
    for v in &rep.insert_at {
        apply(
            &mut log,
            json!({"op": "gc_insert_section", "id": id.0, "part": 1, "v": v}),
        );
    }
    apply(
        &mut log,
        json!({"op": "gc_replace_spine", "id": id.0, "part": 1, "points": rep.points,
               "plane_normal": rep.plane_normal}),
    );
    let asm = assembly(&log, id);
    let gc = &asm.parts[1].gc;
    assert_eq!(gc.sections.len(), rep.plan.params.len());
    let shifted: Vec<DVec3> = stroke
        .iter()
        .map(|p| *p + (old_start - stroke[0]))
        .collect();
    for i in 0..20 {
        let d = to_polyline(ring_centre(gc, i as f64 / 19.0), &shifted);
        assert!(d < 2e-3, "{d}");
    }
    let report = validate(&log.document().get(id).unwrap().mesh, &Default::default());
    assert!(report.is_closed_manifold(), "{}", report.problems());
    assert_eq!(report.components, 1, "the part stays attached");
    assert!(report.signed_volume > one_part.signed_volume);
}
