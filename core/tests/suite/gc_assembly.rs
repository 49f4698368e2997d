//! GC assemblies (§3.3) through the op log: every example script's
//! printable union is a closed 2-manifold with the expected genus;
//! symmetric twins move identically; children stay attached when their
//! parent is edited; a child off its parent's surface is a typed error
//! that leaves the document unchanged; replay is bit-identical.

use crate::common;

use glam::DVec3;
use shapewright::assembly::{
    anchor_frame, detect_relations, mirror_plane, reflect, symmetry_twins, AssemblyError,
    RelationKind,
};
use shapewright::assembly::{ChildEnd, GcAddChild, GcEditPart, GcTransformPart, PartEdit};
use shapewright::doc::{
    parse_script, run_script, Edit, LogError, ObjectId, ObjectKind, Op, OpError, OpLog,
};
use shapewright::gc::{GcAssembly, Profile, Resolution, ShapeType};
use shapewright::gc::{PartId, SectionIndex, SectionSpec};
use shapewright::math::fm::DetMath as _;
use shapewright::mesh::validate;

fn run(name: &str) -> OpLog {
    let path = format!("{}/../tests/data/{name}.jsonl", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example script");
    let lines = parse_script(&text).expect("parses");
    let mut log = OpLog::new();
    run_script(&mut log, &lines).expect("runs");
    log
}

fn assembly(log: &OpLog) -> GcAssembly {
    match &log.document().get(ObjectId(1)).expect("object 1").kind {
        ObjectKind::GcAssembly(a) => a.clone(),
        #[allow(unreachable_patterns)]
        _ => panic!("not an assembly"),
    }
}

#[test]
fn examples_are_closed_manifolds_with_expected_genus() {
    // (name, genus, parts of the assembly, components). The teapot's lid
    // is a separate object closing the opening; its shell spout opens its
    // channel through the body's wall, so the inside is reached through
    // the spout (a blind passage: genus 1, the handle) instead of being a
    // sealed void (a second component before hollow parts kept their
    // cavities empty).
    for (name, genus, parts, components) in [
        ("mug", 1, 2, 1),
        ("teapot", 1, 3, 1),
        ("vase", 0, 1, 1),
        ("funnel", 1, 1, 1),
        ("hammer", 0, 2, 1),
        ("table", 0, 5, 1),
        ("chair", 2, 9, 1),
        ("rack", 1, 8, 1),
    ] {
        let log = run(name);
        assert_eq!(assembly(&log).parts.len(), parts, "{name}: parts");
        let mesh = log.document().printable_mesh().expect("union");
        let r = validate(&mesh, &Default::default());
        assert!(r.is_closed(), "{name}: {}", r.problems());
        assert_eq!(r.non_manifold_vertices, 0, "{name}");
        assert!(r.signed_volume > 0.0, "{name}");
        assert_eq!(r.components, components, "{name}: components");
        assert_eq!(r.genus, Some(genus), "{name}: genus");
    }
}

#[test]
fn teapot_relations_are_detected() {
    let asm = assembly(&run("teapot"));
    let rel = detect_relations(&asm);
    assert!(rel.connected.contains(&(1, 0)), "{rel:?}");
    assert!(rel.connected.contains(&(2, 0)), "{rel:?}");
    // spout and handle are sketched in the same plane through the axis
    assert!(rel.coplanar.contains(&(1, 2)), "{rel:?}");
    let table = assembly(&run("table"));
    let rel = detect_relations(&table);
    // four legs: front/back twins about the top's spine plane
    assert!(rel.symmetric.contains(&(1, 2)), "{rel:?}");
    assert!(rel.symmetric.contains(&(3, 4)), "{rel:?}");
    // legs at the same x are not concentric, the legs are straight and parallel
    assert!(rel.concentric.is_empty(), "{rel:?}");
}

fn assert_mirror_twins(asm: &GcAssembly, a: usize, b: usize) {
    let (o, n) = mirror_plane(&asm.parts[0].gc);
    let (ca, cb) = (common::spine(asm, a), common::spine(asm, b));
    assert_eq!(ca.len(), cb.len());
    for (p, q) in ca.iter().zip(&cb) {
        let d = reflect(*p, o, n).distance(*q);
        assert!(d <= 1e-12, "twin control point off by {d}");
    }
}

#[test]
fn editing_a_chair_leg_moves_its_twin_identically() {
    let mut log = run("chair");
    let asm = assembly(&log);
    assert_eq!(symmetry_twins(&asm, 1), vec![2]);
    let foot = asm.parts[1].gc.key_points()[1];
    log.apply(Op::GcEditPart(Edit::new(
        ObjectId(1),
        GcEditPart {
            part: PartId(1),
            edit: PartEdit::Bend {
                section: SectionIndex(1),
                to: foot + DVec3::new(0.04, 0.0, 0.0),
            },
        },
    )))
    .expect("bend");
    let after = assembly(&log);
    assert!((after.parts[1].gc.key_points()[1] - foot).length() > 0.039);
    assert_mirror_twins(&after, 1, 2);
    // the other legs did not move
    assert_eq!(after.parts[3], asm.parts[3]);
    log.apply(Op::GcEditPart(Edit::new(
        ObjectId(1),
        GcEditPart {
            part: PartId(2),
            edit: PartEdit::Resize {
                section: SectionIndex(0),
                factor: 1.2,
            },
        },
    )))
    .expect("resize");
    let after = assembly(&log);
    assert_eq!(after.parts[1].gc.sections[0].scale, 1.2);
    assert_mirror_twins(&after, 1, 2);
    // Sliding a leg out of the plane it shares with the other legs on its
    // side (and the back post) would break that recorded coplanarity: a
    // typed error naming it, the document unchanged.
    let slide = |translate: DVec3| {
        Op::GcTransformPart(Edit::new(
            ObjectId(1),
            GcTransformPart {
                part: PartId(1),
                translate,
                rotate: [0.0, 0.0, 0.0, 1.0],
                tolerance: 1e-6,
            },
        ))
    };
    let hash = log.document().content_hash();
    match log.apply(slide(DVec3::new(-0.02, -0.01, 0.0))) {
        Err(LogError::Op(OpError::Assembly(AssemblyError::RelationBroken {
            relation: RelationKind::Coplanar,
            parts,
        }))) => assert!(parts.0 == 1 || parts.1 == 1, "{parts:?}"),
        other => panic!("expected a coplanarity refusal, got {other:?}"),
    }
    assert_eq!(log.document().content_hash(), hash);
    // sliding a leg along the seat, in its plane, moves its twin the mirrored way
    log.apply(slide(DVec3::new(-0.02, 0.0, 0.0)))
        .expect("transform");
    let after = assembly(&log);
    assert_mirror_twins(&after, 1, 2);
    let moved = after.parts[1].gc.key_points()[0] - asm.parts[1].gc.key_points()[0];
    assert!(
        (moved - DVec3::new(-0.02, 0.0, 0.0)).length() < 1e-12,
        "{moved}"
    );
    let r = validate(
        &log.document().printable_mesh().expect("union"),
        &Default::default(),
    );
    assert!(r.is_closed());
    // replay from the ops is bit-identical
    let replayed = OpLog::replay(log.ops().to_vec(), log.cursor()).expect("replay");
    assert_eq!(
        replayed.document().content_hash(),
        log.document().content_hash()
    );
}

/// The child's spine start (and a handle's end) in its anchor's frame.
fn local_ends(asm: &GcAssembly, c: usize) -> (DVec3, Option<DVec3>) {
    let p = asm.parts[c].parent.expect("child");
    let att = asm.parts[c].attach.expect("anchored");
    let parent = &asm.parts[p].gc;
    let surf = parent.surface().expect("surface");
    let spine = &asm.parts[c].gc.spine.curve;
    let (a, b) = spine.domain();
    let f0 = anchor_frame(parent, &surf, att.start).expect("frame");
    let start = f0.inverse().transform_point3(spine.point(a));
    let end = att.end.map(|e| {
        anchor_frame(parent, &surf, e)
            .expect("frame")
            .inverse()
            .transform_point3(spine.point(b))
    });
    (start, end)
}

/// Children follow their parent's edits in their anchor frames. The
/// shell spout's root is sunk further in along the body's normal where
/// the body's surface now curves away from its rim (issue 33: without it
/// the rim stood out of the body by 8 mm after this bend and the union's
/// genus went from 1 to 2); the solid handle keeps its coordinates.
#[test]
fn editing_the_body_keeps_children_attached() {
    // Without its lid: the lid is a separate root resting in the opening,
    // which a bend of the body's top moves under it (what was asked).
    let path = format!("{}/../tests/data/teapot.jsonl", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example script");
    let head: String = text.lines().take(3).map(|l| format!("{l}\n")).collect();
    let mut log = OpLog::new();
    run_script(&mut log, &parse_script(&head).expect("parses")).expect("runs");
    let before = assembly(&log);
    let genus = union_report(&log).genus;
    let ends: Vec<_> = (1..3).map(|c| local_ends(&before, c)).collect();
    for edit in [
        PartEdit::Resize {
            section: SectionIndex(2),
            factor: 1.15,
        },
        PartEdit::Bend {
            section: SectionIndex(4),
            to: DVec3::new(0.03, 0.0, 0.17),
        },
    ] {
        log.apply(Op::GcEditPart(Edit::new(
            ObjectId(1),
            GcEditPart {
                part: PartId(0),
                edit,
            },
        )))
        .expect("edit");
    }
    let after = assembly(&log);
    assert_ne!(after.parts[1].gc, before.parts[1].gc, "the spout moved");
    for c in 1..3 {
        let (s0, e0) = ends[c - 1];
        let (s1, e1) = local_ends(&after, c);
        let d = s1 - s0;
        if c == 1 {
            // sunk straight in (local -x: against the body's normal)
            assert!(
                d.x < -0.005 && d.y.fhypot(d.z) <= 1e-9,
                "the spout's root moved by {d}"
            );
        } else {
            assert!(d.length() <= 1e-9, "part {c} start drifted {}", d.length());
        }
        if let (Some(e0), Some(e1)) = (e0, e1) {
            assert!(
                (e1 - e0).length() <= 1e-9,
                "part {c} end drifted {}",
                (e1 - e0).length()
            );
        }
    }
    let r = union_report(&log);
    assert!(r.is_closed(), "{}", r.problems());
    assert_eq!(r.genus, genus, "the spout's root stays closed");
    assert_eq!(r.components, 1);
}

fn child_at(at: DVec3) -> Op {
    Op::GcAddChild(Edit::new(
        ObjectId(1),
        GcAddChild {
            parent: PartId(0),
            at,
            tolerance: 1e-4,
            spine: vec![[-0.005, 0.0], [0.05, 0.0]],
            end: ChildEnd::Free,
            end_tolerance: 1e-4,
            sections: vec![
                SectionSpec {
                    profile: Profile::Circle { radius: 0.01 },
                    v: 0.0,
                    scale: 1.0,
                    twist: 0.0,
                },
                SectionSpec {
                    profile: Profile::Circle { radius: 0.01 },
                    v: 1.0,
                    scale: 1.0,
                    twist: 0.0,
                },
            ],
            shape: ShapeType::Solid,
            resolution: Resolution::PREVIEW,
        },
    ))
}

#[test]
fn child_off_the_parent_surface_is_a_typed_error() {
    let mut log = run("mug");
    let hash = log.document().content_hash();
    let err = log
        .apply(child_at(DVec3::new(0.06, 0.0, 0.05)))
        .expect_err("off surface");
    match err {
        LogError::Op(OpError::Assembly(AssemblyError::OffSurface { distance, .. })) => {
            assert!((distance - 0.0185).abs() < 2e-3, "distance {distance}")
        }
        other => panic!("unexpected {other:?}"),
    }
    assert_eq!(log.document().content_hash(), hash);
    // A NaN pick (lost tracking) is refused at the door, naming the field.
    let err = log.apply(child_at(DVec3::new(f64::NAN, 0.0, 0.05)));
    assert!(matches!(
        err,
        Err(LogError::Op(OpError::BadField { ref field, .. })) if field == "at[0]"
    ));
    let err = log.apply(Op::GcEditPart(Edit::new(
        ObjectId(1),
        GcEditPart {
            part: PartId(7),
            edit: PartEdit::Resize {
                section: SectionIndex(0),
                factor: 1.0,
            },
        },
    )));
    assert!(err.is_err());
    assert_eq!(log.document().content_hash(), hash);
    // on the surface (the radius at v = 0.5 is within 1e-4 of 0.0415) it works
    log.apply(child_at(DVec3::new(0.0, 0.0415, 0.05)))
        .expect("child on the surface");
    assert_eq!(assembly(&log).parts.len(), 3);
}

fn union_report(log: &OpLog) -> shapewright::mesh::ValidationReport {
    validate(
        &log.document().printable_mesh().expect("union"),
        &Default::default(),
    )
}

macro_rules! edit_op {
    ($v:ident, $e:expr) => {
        Op::$v(Edit::new(ObjectId(1), $e))
    };
}

/// Issue 18: replacing the mug body's spine left the handle floating (2
/// components), and a resize from the Blender panel (`gc_resize`)
/// detached one end of the handle (genus 1 to 0). Both now propagate: the
/// handle's ends keep their anchor coordinates and the union keeps its
/// genus.
#[test]
fn mug_spine_replace_and_resize_keep_the_handle_on() {
    use shapewright::gc::{GcReplaceSpine, GcResize};
    let mut log = run("mug");
    let before = assembly(&log);
    let ends0 = local_ends(&before, 1);
    log.apply(edit_op!(
        GcReplaceSpine,
        GcReplaceSpine {
            part: PartId(0),
            points: vec![
                DVec3::ZERO,
                DVec3::new(0.01, 0.0, 0.05),
                DVec3::new(-0.005, 0.0, 0.11),
            ],
            plane_normal: DVec3::Y,
        }
    ))
    .expect("replace spine");
    log.apply(edit_op!(
        GcResize,
        GcResize {
            part: PartId(0),
            section: SectionIndex(3),
            factor: 1.2,
        }
    ))
    .expect("resize");
    let after = assembly(&log);
    assert_ne!(after.parts[1].gc, before.parts[1].gc, "the handle followed");
    let ends1 = local_ends(&after, 1);
    let ds = (ends1.0 - ends0.0).length();
    let de = (ends1.1.expect("handle end") - ends0.1.expect("handle end")).length();
    assert!(
        ds <= 1e-9 && de <= 1e-9,
        "handle drifted: start {ds}, end {de}"
    );
    let r = union_report(&log);
    assert!(r.is_closed(), "{}", r.problems());
    assert_eq!(r.components, 1, "the handle is attached");
    assert_eq!(r.genus, Some(1), "both ends of the handle are attached");
}

/// The angle between a child's spine start tangent and its anchor's
/// surface normal (the child's orientation on its parent).
fn start_angle(asm: &GcAssembly, c: usize) -> f64 {
    let p = asm.parts[c].parent.expect("child");
    let att = asm.parts[c].attach.expect("anchored");
    let parent = &asm.parts[p].gc;
    let surf = parent.surface().expect("surface");
    let f = anchor_frame(parent, &surf, att.start).expect("frame");
    let spine = &asm.parts[c].gc.spine.curve;
    let t = spine.tangent(spine.domain().0).normalize();
    t.dot(f.matrix3.x_axis).clamp(-1.0, 1.0).facos()
}

/// Issue 18: a spout slid over the teapot body kept its old orientation
/// (the union's genus went from 2 to 3). It now turns with the surface
/// normal: its angle to the normal is kept, and so is the genus.
#[test]
fn a_slid_spout_turns_with_the_surface() {
    let mut log = run("teapot");
    let before = assembly(&log);
    let genus = union_report(&log).genus;
    let body = &before.parts[0].gc;
    let surf = body.surface().expect("surface");
    let att = before.parts[1].attach.expect("anchored");
    let anchor = surf.point(att.start.u, att.start.v);
    // dragged 3 cm down the body and projected back on it, as the tool does
    common::slide(&mut log, ObjectId(1), 1, &surf, anchor, -DVec3::Z * 0.03).expect("slide");
    let after = assembly(&log);
    let (a0, a1) = (start_angle(&before, 1), start_angle(&after, 1));
    assert!((a0 - a1).abs() < 1e-9, "angle to the normal {a0} -> {a1}");
    // the body's normal there is not the old one: the spout did turn
    let n0 = anchor_frame(body, &surf, att.start)
        .expect("frame")
        .matrix3
        .x_axis;
    let att1 = after.parts[1].attach.expect("anchored");
    let n1 = anchor_frame(body, &surf, att1.start)
        .expect("frame")
        .matrix3
        .x_axis;
    assert!(
        n0.angle_between(n1) > 0.05,
        "the normal turned by {}",
        n0.angle_between(n1)
    );
    let (s0, s1) = (
        before.parts[1].gc.spine.curve.tangent(0.0),
        after.parts[1].gc.spine.curve.tangent(0.0),
    );
    assert!(s0.angle_between(s1) > 0.05, "the spout turned");
    let r = union_report(&log);
    assert!(r.is_closed(), "{}", r.problems());
    assert_eq!(r.components, 1);
    assert_eq!(r.genus, genus, "a slide does not change the topology");
}

/// Issue 18: the FIST instance always made a mirrored copy; a part in its
/// parent's spine plane (a spout) then landed on the original and was
/// taken for its twin, so dragging the copy dragged the original. A copy
/// is now placed where it is dropped, is never its source's twin unless
/// mirrored (and not lying on it), and moves alone.
#[test]
fn a_copied_spout_is_an_instance_not_a_twin() {
    use shapewright::assembly::GcCopy;
    let mut log = run("teapot");
    let before = assembly(&log);
    // A mirrored copy of an in-plane spout lies on it: not a twin.
    log.apply(edit_op!(
        GcCopy,
        GcCopy {
            part: PartId(1),
            mirror: true,
            translate: DVec3::ZERO,
            rotate: [0.0, 0.0, 0.0, 1.0],
            tolerance: 1e-6,
        }
    ))
    .expect("mirrored copy");
    assert!(symmetry_twins(&assembly(&log), 1).is_empty());
    log.undo().expect("undo");
    // Dropped 2 cm lower on the body, un-mirrored.
    let surf = before.parts[0].gc.surface().expect("surface");
    let att = before.parts[1].attach.expect("anchored");
    let anchor = surf.point(att.start.u, att.start.v);
    let target = shapewright::assembly::project_to_surface(&surf, anchor - DVec3::Z * 0.02).point;
    log.apply(edit_op!(
        GcCopy,
        GcCopy {
            part: PartId(1),
            mirror: false,
            translate: target - anchor,
            rotate: [0.0, 0.0, 0.0, 1.0],
            tolerance: 1e-6,
        }
    ))
    .expect("copy");
    let asm = assembly(&log);
    assert_eq!(asm.parts.len(), 4);
    assert!(symmetry_twins(&asm, 1).is_empty() && symmetry_twins(&asm, 3).is_empty());
    let att3 = asm.parts[3].attach.expect("anchored");
    let d = surf.point(att3.start.u, att3.start.v).distance(target);
    assert!(d < 1e-9, "the copy sits {d} from where it was dropped");
    // dragging the copy leaves the original where it was
    let a3 = surf.point(att3.start.u, att3.start.v);
    common::slide(&mut log, ObjectId(1), 3, &surf, a3, -DVec3::Z * 0.01).expect("drag the copy");
    let after = assembly(&log);
    assert_eq!(after.parts[1], before.parts[1], "the original did not move");
    assert_ne!(after.parts[3], asm.parts[3], "the copy moved");
}

/// An assembly saved before relations were recorded (no `relations`
/// field) loads, gets its relations detected once, and its twins keep
/// following each other from then on.
#[test]
fn assemblies_without_recorded_relations_load_and_get_them() {
    let asm = assembly(&run("chair"));
    let mut json = serde_json::to_value(&asm).expect("serialize");
    assert!(json.get("relations").is_some());
    json.as_object_mut().expect("object").remove("relations");
    let mut old: GcAssembly = serde_json::from_value(json).expect("older form loads");
    assert!(old.relations.is_none());
    assert_eq!(
        symmetry_twins(&old, 1),
        vec![2],
        "detected from the geometry"
    );
    let foot = old.parts[1].gc.key_points()[1];
    GcEditPart {
        part: PartId(1),
        edit: PartEdit::Bend {
            section: SectionIndex(1),
            to: foot + DVec3::new(0.03, 0.0, 0.0),
        },
    }
    .apply_to(&mut old)
    .expect("bend");
    let rec = old.relations.as_ref().expect("recorded now");
    assert_eq!(rec, asm.relations.as_ref().expect("recorded"));
    assert_mirror_twins(&old, 1, 2);
}

/// A refused edit names the relation; `gc_release` lets the user break it.
#[test]
fn released_relations_may_be_broken() {
    use shapewright::assembly::GcRelease;
    let mut log = run("chair");
    let slide = Op::GcTransformPart(Edit::new(
        ObjectId(1),
        GcTransformPart {
            part: PartId(1),
            translate: DVec3::new(0.0, -0.02, 0.0),
            rotate: [0.0, 0.0, 0.0, 1.0],
            tolerance: 1e-6,
        },
    ));
    let mut released = 0;
    loop {
        match log.apply(slide.clone()) {
            Ok(_) => break,
            Err(LogError::Op(OpError::Assembly(AssemblyError::RelationBroken {
                relation,
                parts,
            }))) => {
                assert_eq!(relation, RelationKind::Coplanar);
                log.apply(edit_op!(
                    GcRelease,
                    GcRelease {
                        part: PartId(parts.0),
                        other: PartId(parts.1),
                        relation,
                    }
                ))
                .expect("release");
                released += 1;
                assert!(released <= 8, "releasing does not end");
            }
            Err(e) => panic!("unexpected {e:?}"),
        }
    }
    // legs 1 and 2 left the planes of legs 3, 4 and of the back posts
    assert_eq!(released, 4);
    let asm = assembly(&log);
    assert_mirror_twins(&asm, 1, 2);
    // releasing what is not recorded is a typed error
    let err = log.apply(edit_op!(
        GcRelease,
        GcRelease {
            part: PartId(1),
            other: PartId(3),
            relation: RelationKind::Coplanar,
        }
    ));
    assert!(matches!(
        err,
        Err(LogError::Op(OpError::Assembly(
            AssemblyError::NotRecorded { .. }
        )))
    ));
}
