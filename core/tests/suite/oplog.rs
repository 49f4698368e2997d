//! The op log end to end: undo/redo/replay bit-identity, atomic failures,
//! the redo tail, ids, scripts and their errors.

use shapewright::doc::print_document;
use shapewright::doc::*;
use shapewright::math::Transform;
use shapewright::mesh::validate;
use shapewright::print::PrintSettings;
use shapewright::solid::SolidShape;

fn sphere(r: f64) -> Op {
    Op::AddSolid(AddSolid {
        shape: SolidShape::Sphere { radius: r },
        segments: 16,
        transform: Transform::IDENTITY,
    })
}

fn moved(id: u32, x: f64) -> Op {
    Op::TransformBy(TransformBy {
        id: ObjectId(id),
        transform: Transform::translation([x, 0.0, 0.0]),
    })
}

#[test]
fn ids_are_allocated_in_order_and_never_reused() {
    let mut log = OpLog::new();
    assert_eq!(log.apply(sphere(1.0)).unwrap().created, Some(ObjectId(1)));
    assert_eq!(log.apply(sphere(1.0)).unwrap().created, Some(ObjectId(2)));
    log.apply(Op::Delete(Delete { id: ObjectId(2) })).unwrap();
    assert_eq!(log.apply(sphere(1.0)).unwrap().created, Some(ObjectId(3)));
    let replayed = OpLog::replay(log.ops().to_vec(), log.len()).unwrap();
    assert_eq!(
        replayed.document().content_hash(),
        log.document().content_hash()
    );
    assert_eq!(
        replayed
            .document()
            .objects()
            .map(|(id, _)| id)
            .collect::<Vec<_>>(),
        vec![ObjectId(1), ObjectId(3)]
    );
}

#[test]
fn failed_op_changes_nothing() {
    let mut log = OpLog::new();
    log.apply(sphere(1.0)).unwrap();
    log.apply(moved(1, 2.0)).unwrap();
    log.undo().unwrap();
    let (hash, len, cursor) = (log.document().content_hash(), log.len(), log.cursor());
    let bad = [
        sphere(-1.0),
        sphere(f64::NAN),
        moved(7, 1.0),
        Op::TransformBy(TransformBy {
            id: ObjectId(1),
            transform: Transform {
                scale: [0.0, 1.0, 1.0],
                ..Transform::IDENTITY
            },
        }),
        Op::SetTransform(SetTransform {
            id: ObjectId(1),
            transform: Transform {
                translate: [f64::INFINITY, 0.0, 0.0],
                ..Transform::IDENTITY
            },
        }),
        Op::Delete(Delete { id: ObjectId(0) }),
        Op::EditSolid(Edit::new(
            ObjectId(1),
            EditSolid {
                shape: SolidShape::Torus {
                    major_radius: 1.0,
                    minor_radius: 2.0,
                },
                segments: 32,
            },
        )),
    ];
    for op in bad {
        assert!(log.apply(op.clone()).is_err(), "{op:?} should fail");
        assert_eq!(log.document().content_hash(), hash);
        assert_eq!(
            (log.len(), log.cursor()),
            (len, cursor),
            "the redo tail survives a failed op"
        );
    }
    log.redo().unwrap();
}

#[test]
fn new_op_after_undo_drops_the_redo_tail() {
    let mut log = OpLog::new();
    log.apply(sphere(1.0)).unwrap();
    log.apply(moved(1, 1.0)).unwrap();
    log.apply(moved(1, 1.0)).unwrap();
    log.undo().unwrap();
    log.undo().unwrap();
    log.apply(moved(1, 5.0)).unwrap();
    assert_eq!(log.len(), 2);
    assert_eq!(log.redo(), Err(LogError::NothingToRedo));
    let x = log
        .document()
        .get(ObjectId(1))
        .unwrap()
        .mesh
        .bbox()
        .unwrap()
        .0
        .x;
    assert!((x - 4.0).abs() < 1e-12, "{x}");
}

#[test]
fn undo_and_redo_at_the_ends_are_errors() {
    let mut log = OpLog::new();
    assert_eq!(log.undo(), Err(LogError::NothingToUndo));
    assert_eq!(log.redo(), Err(LogError::NothingToRedo));
    assert_eq!(log.seek(3), Err(LogError::BadCursor { cursor: 3, len: 0 }));
}

/// Undoes every op, then redoes every op, checking the content hash after
/// each step against `hashes` (the document after 0, 1, ... ops).
fn undo_all_then_redo_all(log: &mut OpLog, hashes: &[u64]) {
    for k in (0..log.len()).rev() {
        log.undo().unwrap();
        assert_eq!(log.document().content_hash(), hashes[k], "undo to {k}");
    }
    for (k, h) in hashes.iter().enumerate().skip(1) {
        log.redo().unwrap();
        assert_eq!(log.document().content_hash(), *h, "redo to {k}");
    }
}

#[test]
fn long_history_keeps_checkpoints_and_undo_matches_replay() {
    let mut log = OpLog::with_policy(CheckpointPolicy {
        every_ops: 10,
        every_work: u64::MAX,
        ..Default::default()
    });
    log.apply(sphere(0.5)).unwrap();
    let mut hashes = vec![
        Document::new().content_hash(),
        log.document().content_hash(),
    ];
    for i in 0..95 {
        log.apply(moved(1, 0.01 * i as f64)).unwrap();
        hashes.push(log.document().content_hash());
    }
    assert!(log.checkpoint_count() >= 9, "{}", log.checkpoint_count());
    undo_all_then_redo_all(&mut log, &hashes);
}

/// Issue 21: old checkpoints are thinned (the newest `dense` kept, older
/// ones at doubling gaps), so their number grows with the log's logarithm;
/// undo all the way back still matches replay at every step.
#[test]
fn old_checkpoints_thin_out_and_undo_still_matches_replay() {
    let policy = CheckpointPolicy {
        every_ops: 5,
        every_work: u64::MAX,
        dense: 4,
    };
    let mut log = OpLog::with_policy(policy);
    log.apply(sphere(0.5)).unwrap();
    let mut hashes = vec![
        Document::new().content_hash(),
        log.document().content_hash(),
    ];
    let mut most = 0;
    for i in 0..600 {
        log.apply(moved(1, 0.001 * i as f64)).unwrap();
        hashes.push(log.document().content_hash());
        most = most.max(log.checkpoint_count());
    }
    // 120 checkpoints taken; kept: 0, the 4 newest, and at most one per
    // doubling of the gap (600 / 10 < 2^6).
    assert!(most <= 1 + 4 + 7, "{most}");
    assert!(log.checkpoint_count() > 4, "{}", log.checkpoint_count());
    undo_all_then_redo_all(&mut log, &hashes);
}

#[test]
fn from_snapshot_reopens_without_replay_and_undoes() {
    let mut log = OpLog::new();
    log.apply(sphere(0.5)).unwrap();
    let mut hashes = vec![
        Document::new().content_hash(),
        log.document().content_hash(),
    ];
    for i in 0..40 {
        log.apply(moved(1, 0.1 * i as f64)).unwrap();
        hashes.push(log.document().content_hash());
    }
    let mut reopened =
        OpLog::from_snapshot(log.ops().to_vec(), log.cursor(), log.document().clone()).unwrap();
    for k in (0..log.len()).rev() {
        reopened.undo().unwrap();
        assert_eq!(reopened.document().content_hash(), hashes[k]);
    }
}

#[test]
fn meshes_carry_their_object_id_and_validate() {
    let mut log = OpLog::new();
    log.apply(sphere(0.5)).unwrap();
    log.apply(Op::Duplicate(Duplicate { id: ObjectId(1) }))
        .unwrap();
    for (id, obj) in log.document().objects() {
        assert!(obj.mesh.tri_source.iter().all(|&s| s == id.0));
        assert!(validate(&obj.mesh, &Default::default()).is_closed_manifold());
    }
}

#[test]
fn script_runs_and_errors_name_the_line() {
    let text = "# demo\n{\"op\":\"add_solid\",\"shape\":{\"kind\":\"box\",\"size\":[1,1,1]}}\n\n{\"op\":\"undo\"}\n{\"op\":\"redo\"}\n";
    let lines = parse_script(text).unwrap();
    assert_eq!(
        lines.iter().map(|l| l.line).collect::<Vec<_>>(),
        vec![2, 4, 5]
    );
    let mut log = OpLog::new();
    run_script(&mut log, &lines).unwrap();
    assert_eq!(log.document().len(), 1);

    let err = |t: &str| parse_script(t).unwrap_err();
    assert!(matches!(err("\n{nope").kind, ScriptErrorKind::Json(_)) && err("\n{nope").line == 2);
    assert_eq!(
        err("{\"op\":\"explode\"}").kind,
        ScriptErrorKind::UnknownOp {
            name: "explode".into()
        }
    );
    assert_eq!(err("[1,2]").kind, ScriptErrorKind::NotAnOp);
    assert_eq!(
        err("{\"v\":99,\"op\":\"undo\"}").kind,
        ScriptErrorKind::UnsupportedVersion(99)
    );
    let missing = err("{\"op\":\"add_solid\",\"shape\":{\"kind\":\"sphere\"}}");
    assert!(
        matches!(&missing.kind, ScriptErrorKind::Json(m) if m.contains("radius")),
        "{missing}"
    );
    let unknown_field = err("{\"op\":\"delete\",\"id\":1,\"force\":true}");
    assert!(
        matches!(&unknown_field.kind, ScriptErrorKind::Json(m) if m.contains("force")),
        "{unknown_field}"
    );
    let huge = err("{\"op\":\"add_solid\",\"shape\":{\"kind\":\"sphere\",\"radius\":1e999}}");
    assert!(matches!(huge.kind, ScriptErrorKind::Json(_)));

    // Run-time errors: zero size, deleted id. Earlier lines stay applied.
    let lines =
        parse_script("{\"op\":\"add_solid\",\"shape\":{\"kind\":\"box\",\"size\":[1,0,1]}}")
            .unwrap();
    let e = run_script(&mut OpLog::new(), &lines).unwrap_err();
    assert_eq!(e.line, 1);
    assert!(e.to_string().contains("size[1]"), "{e}");
    let lines = parse_script("{\"op\":\"add_solid\",\"shape\":{\"kind\":\"sphere\",\"radius\":1}}\n{\"op\":\"delete\",\"id\":1}\n{\"op\":\"delete\",\"id\":1}").unwrap();
    let mut log = OpLog::new();
    let e = run_script(&mut log, &lines).unwrap_err();
    assert_eq!(
        (e.line, e.kind),
        (
            3,
            ScriptErrorKind::Log(LogError::Op(OpError::BadId(ObjectId(1))))
        )
    );
    assert_eq!(log.cursor(), 2);
}

#[test]
fn ops_round_trip_through_json_exactly() {
    let op = Op::TransformBy(TransformBy {
        id: ObjectId(4),
        transform: Transform {
            translate: [0.1, 1.0 / 3.0, -2e-17],
            rotate: [0.0, 0.0, 0.3826834323650898, 0.9238795325112867],
            scale: [1.5; 3],
        },
    });
    let json = serde_json::to_string(&op).unwrap();
    assert!(json.starts_with("{\"op\":\"transform_by\""), "{json}");
    assert_eq!(serde_json::from_str::<Op>(&json).unwrap(), op);
    for name in OP_NAMES {
        let text = format!("{{\"op\":\"{name}\"}}");
        let e = parse_script(&text).unwrap_err();
        assert!(
            !matches!(e.kind, ScriptErrorKind::UnknownOp { .. }),
            "{name} must be a known op"
        );
    }
}

#[test]
fn bundled_scripts_build_closed_meshes() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    let mut ran = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        // `NAME.trace.jsonl` files are input traces (interact), not op scripts.
        let is_trace = path.to_string_lossy().ends_with(".trace.jsonl");
        if path.extension().is_some_and(|e| e == "jsonl") && !is_trace {
            let lines = parse_script(&std::fs::read_to_string(&path).unwrap()).unwrap();
            let mut log = OpLog::new();
            run_script(&mut log, &lines).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            for (id, obj) in log.document().objects() {
                // A curve network may be an open surface (the lampshade):
                // the print path below thickens it; every solid is closed.
                if matches!(obj.kind, ObjectKind::CurveNetwork(_)) {
                    continue;
                }
                let r = validate(&obj.mesh, &Default::default());
                assert!(
                    r.is_closed_manifold(),
                    "{} object {id}: {}",
                    path.display(),
                    r.problems()
                );
            }
            // Every bundled model prints: one closed 2-manifold at float32.
            let printed = print_document(log.document(), &PrintSettings::default())
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert!(validate(&printed.mesh, &Default::default()).is_closed_manifold());
            let replayed = OpLog::replay(log.ops().to_vec(), log.cursor()).unwrap();
            assert_eq!(
                replayed.document().content_hash(),
                log.document().content_hash()
            );
            ran += 1;
        }
    }
    assert!(ran >= 1);
}
