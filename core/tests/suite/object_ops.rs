//! Every object kind moves, rotates, scales, duplicates, deletes and is
//! renamed through the document ops, with undo, redo and bit-identical
//! replay (issue 19's "every object movable", issue 15's `rename_object`).

use std::path::Path;

use shapewright::doc::*;
use shapewright::math::{DAffine3, DQuat, DVec3, Transform};
use shapewright::mesh::validate;

/// A log holding one object of each kind, built from the fixtures' first
/// ops: (kind, id).
fn every_kind() -> (OpLog, Vec<(&'static str, ObjectId)>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    let mut log = OpLog::new();
    let mut out = Vec::new();
    for (kind, file, lines) in [
        ("solid", "primitives.jsonl", 1),
        ("gc_assembly", "vase.jsonl", usize::MAX),
        ("sdf_volume", "csg_cup.jsonl", usize::MAX),
        ("curve_network", "curve_network.jsonl", usize::MAX),
        ("sculpt_mesh", "bust.jsonl", 3),
    ] {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let first = log.document().next_id();
        for l in parse_script(&text).unwrap().into_iter().take(lines) {
            if let ScriptCommand::Op(mut op) = l.command {
                // Renumber object references: each fixture starts at id 1.
                renumber(&mut op, first.0 - 1);
                log.apply(op).unwrap();
            }
        }
        assert_eq!(log.document().get(first).unwrap().kind.name(), kind);
        out.push((kind, first));
    }
    (log, out)
}

fn renumber(op: &mut Op, by: u32) {
    let mut v = serde_json::to_value(&*op).unwrap();
    for key in ["id", "volume"] {
        if let Some(x) = v.get_mut(key) {
            *x = (x.as_u64().unwrap() + by as u64).into();
        }
    }
    *op = serde_json::from_value(v).unwrap();
}

fn apply(log: &mut OpLog, json: serde_json::Value) -> Result<OpOutcome, LogError> {
    log.apply(serde_json::from_value(json).unwrap())
}

#[test]
fn every_kind_moves_rotates_and_scales_exactly() {
    let (mut log, objects) = every_kind();
    let q = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
    let t = Transform {
        translate: [0.3, -0.2, 0.15],
        rotate: q.to_array(),
        scale: [1.5; 3],
    };
    for (kind, id) in objects {
        let before = log.document().get(id).unwrap().clone();
        let vol0 = validate(&before.mesh, &Default::default()).signed_volume;
        let hash0 = log.document().content_hash();
        apply(
            &mut log,
            serde_json::json!({"op":"set_transform","id":id.0,"transform":t}),
        )
        .unwrap_or_else(|e| panic!("{kind}: {e}"));
        let after = log.document().get(id).unwrap();
        assert_eq!(after.transform(), t, "{kind}");
        let a: DAffine3 = t.to_affine().unwrap();
        // Solids and sculpts re-mesh from their own transform; the other
        // kinds move their own mesh once: both land where the affine says.
        let local = &before.local_mesh;
        let base = before.transform().to_affine().unwrap().inverse();
        let mut worst: f64 = 0.0;
        for (p, q) in local.positions.iter().zip(after.mesh.positions.iter()) {
            let want = a.transform_point3(base.transform_point3(DVec3::from_array(*p)));
            let want = if before.kind.own_transform().is_some() {
                want
            } else {
                a.transform_point3(DVec3::from_array(*p))
            };
            worst = worst.max((want - DVec3::from_array(*q)).length());
        }
        assert!(worst < 1e-9, "{kind}: moved mesh off by {worst}");
        let vol1 = validate(&after.mesh, &Default::default()).signed_volume;
        if vol0.abs() > 1e-9 {
            assert!(
                (vol1 / vol0 - 3.375).abs() < 1e-6,
                "{kind}: volume ratio {}",
                vol1 / vol0
            );
        }
        assert_ne!(log.document().content_hash(), hash0, "{kind}");
        log.undo().unwrap();
        assert_eq!(log.document().content_hash(), hash0, "{kind}: undo");
        log.redo().unwrap();
    }
    let replayed = OpLog::replay(log.ops().to_vec(), log.cursor()).unwrap();
    assert_eq!(
        replayed.document().content_hash(),
        log.document().content_hash()
    );
}

#[test]
fn transform_by_composes_and_edits_keep_the_placement() {
    let (mut log, objects) = every_kind();
    let (_, gc) = objects[1];
    for _ in 0..3 {
        apply(
            &mut log,
            serde_json::json!({"op":"transform_by","id":gc.0,"transform":{"translate":[0.1,0,0]}}),
        )
        .unwrap();
    }
    let t = log.document().get(gc).unwrap().transform();
    assert!((t.translate[0] - 0.3).abs() < 1e-15, "{t:?}");
    // An edit of the moved assembly re-meshes it in its own frame and keeps
    // the placement.
    apply(
        &mut log,
        serde_json::json!({"op":"gc_resize","id":gc.0,"section":0,"factor":1.1}),
    )
    .unwrap();
    let obj = log.document().get(gc).unwrap();
    assert_eq!(obj.transform(), t);
    let (lo, _) = obj.mesh.bbox().unwrap();
    let (llo, _) = obj.local_mesh.bbox().unwrap();
    assert!((lo.x - llo.x - 0.3).abs() < 1e-12);
}

#[test]
fn duplicate_rename_and_delete_every_kind() {
    let (mut log, objects) = every_kind();
    for (kind, id) in objects {
        apply(
            &mut log,
            serde_json::json!({"op":"set_transform","id":id.0,"transform":{"translate":[0.0,0.5,0.0]}}),
        )
        .unwrap();
        let copy = apply(&mut log, serde_json::json!({"op":"duplicate","id":id.0}))
            .unwrap()
            .created
            .unwrap();
        let (a, b) = (
            log.document().get(id).unwrap(),
            log.document().get(copy).unwrap(),
        );
        assert_eq!(a.kind, b.kind, "{kind}");
        assert_eq!(a.transform(), b.transform(), "{kind}");
        assert_eq!(a.mesh.positions, b.mesh.positions, "{kind}");
        assert!(b.mesh.tri_source.iter().all(|s| *s == copy.0), "{kind}");
        // The copy moves on its own.
        apply(
            &mut log,
            serde_json::json!({"op":"transform_by","id":copy.0,"transform":{"translate":[0.2,0,0]}}),
        )
        .unwrap();
        let geometry = log.document().get(copy).unwrap().mesh.clone();
        apply(
            &mut log,
            serde_json::json!({"op":"rename_object","id":copy.0,"name":format!("{kind} copy")}),
        )
        .unwrap();
        let renamed = log.document().get(copy).unwrap();
        assert_eq!(renamed.name, format!("{kind} copy"));
        assert_eq!(renamed.mesh, geometry, "renaming changes no geometry");
        apply(&mut log, serde_json::json!({"op":"delete","id":copy.0})).unwrap();
        assert!(log.document().get(copy).is_err());
    }
    // Names survive the document's own serialization (USD snapshots).
    apply(
        &mut log,
        serde_json::json!({"op":"rename_object","id":1,"name":"base"}),
    )
    .unwrap();
    let text = serde_json::to_string(log.document()).unwrap();
    let back: Document = serde_json::from_str(&text).unwrap();
    assert_eq!(back.content_hash(), log.document().content_hash());
    let replayed = OpLog::replay(log.ops().to_vec(), log.cursor()).unwrap();
    assert_eq!(
        replayed.document().content_hash(),
        log.document().content_hash()
    );
}

#[test]
fn bad_placements_and_names_are_refused_and_change_nothing() {
    let (mut log, objects) = every_kind();
    let hash = log.document().content_hash();
    let (_, sculpt) = objects[4];
    let (_, gc) = objects[1];
    for (json, needle) in [
        (
            serde_json::json!({"op":"set_transform","id":sculpt.0,"transform":{"scale":[1,2,1]}}),
            "scale",
        ),
        (
            serde_json::json!({"op":"set_transform","id":gc.0,"transform":{"scale":[0,1,1]}}),
            "scale",
        ),
        (
            serde_json::json!({"op":"set_transform","id":gc.0,"transform":{"translate":[1e6,0,0]}}),
            "transform.translate[0]",
        ),
        (
            serde_json::json!({"op":"rename_object","id":gc.0,"name":"a\u{7}b"}),
            "control characters",
        ),
        (
            serde_json::json!({"op":"rename_object","id":99,"name":"x"}),
            "does not exist",
        ),
    ] {
        let err = apply(&mut log, json.clone()).unwrap_err().to_string();
        assert!(err.contains(needle), "{json}: {err}");
    }
    assert_eq!(log.document().content_hash(), hash);
    // A rotated object refuses a non-uniform increment that would shear.
    apply(
        &mut log,
        serde_json::json!({"op":"set_transform","id":gc.0,"transform":{"rotate":[0,0,0.38268343236,0.92387953251]}}),
    )
    .unwrap();
    let err = apply(
        &mut log,
        serde_json::json!({"op":"transform_by","id":gc.0,"transform":{"scale":[1,2,1]}}),
    )
    .unwrap_err();
    assert!(err.to_string().contains("shear"), "{err}");
}
