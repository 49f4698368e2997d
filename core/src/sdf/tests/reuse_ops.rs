//! The fused-result ops through the document log: `sdf_move_fused`,
//! `sdf_copy_fused` and `sdf_component_from_object` do what they say
//! (volumes and positions measured), replay bit for bit, undo to the
//! document before them, and refuse bad input with typed errors that
//! change nothing.

use crate::doc::{parse_script, LogError, ObjectId, ObjectKind, Op, OpError, OpLog, ScriptCommand};
use crate::math::{DQuat, DVec3, Transform};
use crate::mesh::{validate, TriMesh};
use crate::sdf::SdfError;

fn op(json: &str) -> Op {
    serde_json::from_str(json).unwrap_or_else(|e| panic!("{json}: {e}"))
}

fn closed(m: &TriMesh) -> crate::mesh::ValidationReport {
    let r = validate(m, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    r
}

fn centre(m: &TriMesh) -> DVec3 {
    let (a, b) = m.bbox().unwrap();
    (a + b) * 0.5
}

/// A bowl: a sphere minus a smaller, raised sphere (not symmetric in z, so
/// a rotation shows).
fn bowl() -> OpLog {
    let mut log = OpLog::new();
    for l in [
        r#"{"op":"sdf_create","step":0.01}"#,
        r#"{"op":"sdf_add_operand","volume":1,"component":{"kind":"solid","shape":{"kind":"sphere","radius":0.1}},"csg":"union"}"#,
        r#"{"op":"sdf_add_operand","volume":1,"component":{"kind":"solid","shape":{"kind":"sphere","radius":0.08}},"csg":"subtract","transform":{"translate":[0,0,0.06],"rotate":[0,0,0,1],"scale":[1,1,1]}}"#,
        r#"{"op":"sdf_update","volume":1}"#,
    ] {
        log.apply(op(l)).unwrap();
    }
    log
}

fn mesh(log: &OpLog, id: u32) -> TriMesh {
    (*log.document().get(ObjectId(id)).unwrap().mesh).clone()
}

fn replays_and_undoes(log: &mut OpLog, before: u64) {
    let hash = log.document().content_hash();
    let again = OpLog::replay(log.ops().to_vec(), log.len()).unwrap();
    assert_eq!(again.document().content_hash(), hash, "replay");
    let last = log.ops().last().unwrap().clone();
    let line = serde_json::to_string(&last).unwrap();
    assert_eq!(
        parse_script(&line).unwrap()[0].command,
        ScriptCommand::Op(last),
        "{line}"
    );
    log.undo().unwrap();
    assert_eq!(log.document().content_hash(), before, "undo");
    log.redo().unwrap();
    assert_eq!(log.document().content_hash(), hash, "redo");
}

fn sdf_err(e: LogError) -> SdfError {
    match e {
        LogError::Op(OpError::Sdf(s)) => s,
        other => panic!("not an SDF error: {other:?}"),
    }
}

#[test]
fn moving_the_fused_result_moves_the_solid() {
    let mut log = bowl();
    let m0 = mesh(&log, 1);
    let r0 = closed(&m0);
    let before = log.document().content_hash();
    let q = DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
    let t = Transform {
        translate: [0.2, -0.1, 0.05],
        rotate: q.to_array(),
        scale: [0.8; 3],
    };
    log.apply(op(&format!(
        r#"{{"op":"sdf_move_fused","volume":1,"transform":{}}}"#,
        serde_json::to_string(&t).unwrap()
    )))
    .unwrap();
    let m1 = mesh(&log, 1);
    let r1 = closed(&m1);
    assert_eq!(r1.genus, r0.genus);
    let ratio = r1.signed_volume / (0.512 * r0.signed_volume);
    assert!((ratio - 1.0).abs() < 0.03, "volume ratio {ratio}");
    // The same as building the moved recipe from scratch at the step the
    // shrink resamples at (0.01 * 0.8: as many cells across as before).
    let mut fresh = log.clone();
    for l in [
        r#"{"op":"sdf_create","step":0.008}"#.to_string(),
        format!(
            r#"{{"op":"sdf_add_operand","volume":2,"component":{{"kind":"solid","shape":{{"kind":"sphere","radius":0.1}}}},"csg":"union","transform":{}}}"#,
            serde_json::to_string(&t).unwrap()
        ),
        format!(
            r#"{{"op":"sdf_add_operand","volume":2,"component":{{"kind":"solid","shape":{{"kind":"sphere","radius":0.08}}}},"csg":"subtract","transform":{}}}"#,
            serde_json::to_string(&Transform {
                translate: (DVec3::from_array(t.translate) + q * DVec3::new(0.0, 0.0, 0.06 * 0.8))
                    .to_array(),
                ..t
            })
            .unwrap()
        ),
        r#"{"op":"sdf_update","volume":2}"#.to_string(),
    ] {
        fresh.apply(op(&l)).unwrap();
    }
    let rf = closed(&mesh(&fresh, 2));
    assert!(
        (r1.signed_volume / rf.signed_volume - 1.0).abs() < 0.005,
        "{} vs {}",
        r1.signed_volume,
        rf.signed_volume
    );
    // The bowl's opening (+z) now faces -y; its centre moved by t.
    let want = DVec3::from_array(t.translate) + q * (centre(&m0) * 0.8);
    assert!(
        (centre(&m1) - want).length() < 0.01,
        "{} vs {want}",
        centre(&m1)
    );
    let (lo, hi) = m1.bbox().unwrap();
    let (lo0, hi0) = m0.bbox().unwrap();
    assert!(((hi.x - lo.x) - 0.8 * (hi0.x - lo0.x)).abs() < 0.01);
    replays_and_undoes(&mut log, before);
    // A per-axis scale is no similarity: typed, nothing changed.
    let hash = log.document().content_hash();
    let e = log
        .apply(op(r#"{"op":"sdf_move_fused","volume":1,"transform":{"translate":[0,0,0],"rotate":[0,0,0,1],"scale":[1,2,1]}}"#))
        .unwrap_err();
    assert!(matches!(sdf_err(e), SdfError::NotSimilarity(_)));
    assert_eq!(log.document().content_hash(), hash);
    // Nothing fused yet: typed.
    log.apply(op(r#"{"op":"sdf_create","step":0.01}"#)).unwrap();
    let e = log
        .apply(op(r#"{"op":"sdf_move_fused","volume":2,"transform":{"translate":[0.1,0,0],"rotate":[0,0,0,1],"scale":[1,1,1]}}"#))
        .unwrap_err();
    assert_eq!(sdf_err(e), SdfError::EmptyResult);
}

#[test]
fn copying_the_fused_result_queues_it_as_a_component() {
    let mut log = bowl();
    let m0 = mesh(&log, 1);
    let r0 = closed(&m0);
    let before = log.document().content_hash();
    log.apply(op(r#"{"op":"sdf_copy_fused","volume":1,"name":"bowl","csg":"union","transform":{"translate":[0.3,0,0],"rotate":[0,0,0,1],"scale":[1,1,1]}}"#))
        .unwrap();
    {
        let ObjectKind::SdfVolume(v) = &log.document().get(ObjectId(1)).unwrap().kind else {
            panic!()
        };
        assert_eq!(v.pending.len(), 1);
        assert!(v.user_components.contains_key("bowl"));
    }
    replays_and_undoes(&mut log, before);
    log.apply(op(r#"{"op":"sdf_update","volume":1}"#)).unwrap();
    let m = mesh(&log, 1);
    let r = closed(&m);
    assert_eq!(r.components, 2, "the bowl and its copy beside it");
    let ratio = r.signed_volume / (2.0 * r0.signed_volume);
    assert!((ratio - 1.0).abs() < 0.03, "volume ratio {ratio}");
    let (lo, hi) = m.bbox().unwrap();
    let (lo0, hi0) = m0.bbox().unwrap();
    assert!((hi.x - (hi0.x + 0.3)).abs() < 0.01 && (lo.x - lo0.x).abs() < 1e-9);
    // Names: taken or empty, typed.
    let hash = log.document().content_hash();
    for (json, want) in [
        (
            r#"{"op":"sdf_copy_fused","volume":1,"name":"bowl","csg":"union"}"#,
            SdfError::DuplicateComponent("bowl".into()),
        ),
        (
            r#"{"op":"sdf_copy_fused","volume":1,"name":"","csg":"union"}"#,
            SdfError::EmptyComponentName,
        ),
    ] {
        assert_eq!(sdf_err(log.apply(op(json)).unwrap_err()), want);
        assert_eq!(log.document().content_hash(), hash);
    }
}

#[test]
fn any_closed_object_becomes_a_component_where_it_is() {
    let mut log = OpLog::new();
    log.apply(op(r#"{"op":"add_solid","shape":{"kind":"box","size":[0.2,0.1,0.15]},"transform":{"translate":[0.1,0.05,0.2],"rotate":[0,0,0.3826834323650898,0.9238795325112867],"scale":[1,1,1]}}"#))
        .unwrap();
    // The volume is placed elsewhere: the component is taken into its frame.
    log.apply(op(r#"{"op":"sdf_create","step":0.01}"#)).unwrap();
    log.apply(op(r#"{"op":"set_transform","id":2,"transform":{"translate":[-0.3,0.1,0],"rotate":[0.0,0.0,0.0,1.0],"scale":[1,1,1]}}"#))
        .unwrap();
    let before = log.document().content_hash();
    log.apply(op(
        r#"{"op":"sdf_component_from_object","volume":2,"object":1,"name":"block","csg":"union"}"#,
    ))
    .unwrap();
    replays_and_undoes(&mut log, before);
    log.apply(op(r#"{"op":"sdf_update","volume":2}"#)).unwrap();
    let src = mesh(&log, 1);
    let got = mesh(&log, 2);
    let r = closed(&got);
    let want = 0.2 * 0.1 * 0.15;
    assert!(
        (r.signed_volume / want - 1.0).abs() < 0.03,
        "{}",
        r.signed_volume
    );
    // Placed, the volume's result sits where the box is.
    assert!(
        (centre(&got) - centre(&src)).length() < 0.005,
        "{} vs {}",
        centre(&got),
        centre(&src)
    );
    let (lo, hi) = got.bbox().unwrap();
    let (lo0, hi0) = src.bbox().unwrap();
    assert!((lo - lo0).abs().max_element() < 0.01 && (hi - hi0).abs().max_element() < 0.01);
    // Without `csg`: stored, not queued.
    log.apply(op(
        r#"{"op":"sdf_component_from_object","volume":2,"object":1,"name":"block2"}"#,
    ))
    .unwrap();
    let ObjectKind::SdfVolume(v) = &log.document().get(ObjectId(2)).unwrap().kind else {
        panic!()
    };
    assert!(v.pending.is_empty() && v.user_components.len() == 2);
    // Bad input: typed, nothing changed.
    let hash = log.document().content_hash();
    let e = log
        .apply(op(
            r#"{"op":"sdf_component_from_object","volume":2,"object":9,"name":"x"}"#,
        ))
        .unwrap_err();
    assert!(
        matches!(e, LogError::Op(OpError::BadId(ObjectId(9)))),
        "{e:?}"
    );
    let e = log
        .apply(op(
            r#"{"op":"sdf_component_from_object","volume":2,"object":1,"name":"block"}"#,
        ))
        .unwrap_err();
    assert_eq!(sdf_err(e), SdfError::DuplicateComponent("block".into()));
    assert_eq!(log.document().content_hash(), hash);
}
