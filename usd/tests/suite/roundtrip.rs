//! Document -> USD -> document: same ops, same cursor, bit-identical meshes;
//! undo/redo after reopening; versions; geometry/log disagreement.

use crate::common;

use openusd::sdf::{self, AbstractData, Value};
use shapewright::doc::OpLog;
use shapewright_usd::{
    load_file, load_from_str, save_file, save_to_string, LoadError, LoadOptions, Mismatch,
    SaveOptions,
};

fn verify() -> LoadOptions {
    LoadOptions {
        verify_history: true,
        strict: false,
    }
}

#[test]
fn every_script_round_trips_bit_identically() {
    let scripts = common::scripts();
    assert!(scripts.len() >= 3, "found {} scripts", scripts.len());
    for (path, text) in scripts {
        let log = common::run(&text);
        let usda = save_to_string(&log, &SaveOptions::default()).unwrap();
        let loaded = load_from_str(&usda, verify()).unwrap();
        let name = path.display();
        assert_eq!(loaded.log.ops(), log.ops(), "{name}: ops");
        assert_eq!(loaded.log.cursor(), log.cursor(), "{name}: cursor");
        assert_eq!(
            loaded.log.document().content_hash(),
            log.document().content_hash(),
            "{name}: document"
        );
        assert!(loaded.report.is_consistent(), "{name}: {}", loaded.report);
        assert!(loaded.report.history_checked);
        assert_eq!(loaded.report.objects_checked, log.document().len());
        assert!(!loaded.replayed);
        // Saving the reopened log gives the same text.
        let again = save_to_string(&loaded.log, &SaveOptions::default()).unwrap();
        assert_eq!(again, usda, "{name}: second save differs");
    }
}

#[test]
fn undo_and_redo_work_after_reopening() {
    for (path, text) in common::scripts() {
        let log = common::run(&text);
        let usda = save_to_string(&log, &SaveOptions::default()).unwrap();
        let mut reopened = load_from_str(&usda, LoadOptions::default()).unwrap().log;
        let mut reference = log.clone();
        // Undo to the start, then redo past the saved cursor to the end.
        while reference.can_undo() {
            reference.undo().unwrap();
            reopened.undo().unwrap();
            assert_eq!(
                reopened.document().content_hash(),
                reference.document().content_hash(),
                "{}: after undo to {}",
                path.display(),
                reference.cursor()
            );
        }
        assert!(!reopened.can_undo());
        while reference.can_redo() {
            reference.redo().unwrap();
            reopened.redo().unwrap();
            assert_eq!(
                reopened.document().content_hash(),
                reference.document().content_hash(),
                "{}: after redo to {}",
                path.display(),
                reference.cursor()
            );
        }
        assert!(!reopened.can_redo());
    }
}

#[test]
fn redo_tail_survives_and_new_op_drops_it() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/solids_edits.jsonl"
    ))
    .unwrap();
    let log = common::run(&text);
    assert!(log.can_redo(), "the script ends with a redo tail");
    let usda = save_to_string(&log, &SaveOptions::default()).unwrap();
    let mut reopened = load_from_str(&usda, LoadOptions::default()).unwrap().log;
    assert_eq!(reopened.len(), log.len());
    assert!(reopened.can_redo());
    let op = log.ops()[0].clone();
    reopened.apply(op).unwrap();
    assert!(!reopened.can_redo());
    assert_eq!(reopened.len(), log.cursor() + 1);
}

#[test]
fn stage_metadata_and_mesh_schema_are_authored() {
    let (_, text) = common::scripts()
        .into_iter()
        .find(|(p, _)| p.ends_with("solids_basic.jsonl"))
        .unwrap();
    let log = common::run(&text);
    let usda = save_to_string(
        &log,
        &SaveOptions {
            meters_per_unit: 0.5,
        },
    )
    .unwrap();
    let data = openusd::usda::parse(&usda).unwrap();
    let root = sdf::Path::abs_root();
    let f = |p: &sdf::Path, k: &str| data.try_field(p, k).unwrap().map(|v| v.into_owned());
    assert_eq!(f(&root, "defaultPrim"), Some(Value::Token("World".into())));
    assert_eq!(f(&root, "upAxis"), Some(Value::Token("Z".into())));
    assert_eq!(f(&root, "metersPerUnit"), Some(Value::Double(0.5)));
    let loaded = load_from_str(&usda, LoadOptions::default()).unwrap();
    assert_eq!(loaded.meters_per_unit, 0.5);
    for (id, obj) in log.document().objects() {
        let mesh = sdf::path(format!("/World/Object_{}/Mesh", id.0)).unwrap();
        assert_eq!(f(&mesh, "typeName"), Some(Value::Token("Mesh".into())));
        let attr = |n: &str| f(&mesh.append_property(n).unwrap(), "default");
        let Some(Value::Vec3fVec(points)) = attr("points") else {
            panic!("points")
        };
        assert_eq!(points.len(), obj.mesh.positions.len());
        for (p, q) in points.iter().zip(&obj.mesh.positions) {
            assert_eq!([p.x, p.y, p.z], q.map(|x| x as f32));
        }
        let Some(Value::IntVec(idx)) = attr("faceVertexIndices") else {
            panic!("indices")
        };
        let flat: Vec<i32> = obj
            .mesh
            .triangles
            .iter()
            .flatten()
            .map(|&i| i as i32)
            .collect();
        assert_eq!(idx, flat);
        let Some(Value::IntVec(counts)) = attr("faceVertexCounts") else {
            panic!("counts")
        };
        assert!(counts.len() == obj.mesh.triangles.len() && counts.iter().all(|&c| c == 3));
        let Some(Value::Vec3fVec(normals)) = attr("normals") else {
            panic!("normals")
        };
        assert_eq!(normals.len(), points.len());
        let Some(Value::Vec3fVec(extent)) = attr("extent") else {
            panic!("extent")
        };
        let (lo, hi) = obj.mesh.bbox().unwrap();
        assert_eq!(
            [extent[0].x, extent[0].y, extent[0].z],
            lo.to_array().map(|x| x as f32)
        );
        assert_eq!(
            [extent[1].x, extent[1].y, extent[1].z],
            hi.to_array().map(|x| x as f32)
        );
    }
}

fn saved_edits() -> (OpLog, String) {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/solids_edits.jsonl"
    ))
    .unwrap();
    let log = common::run(&text);
    let usda = save_to_string(&log, &SaveOptions::default()).unwrap();
    (log, usda)
}

#[test]
fn older_and_newer_format_versions_give_clear_errors() {
    let (_, usda) = saved_edits();
    let line = "custom uniform int shapewright:formatVersion = 1";
    assert!(usda.contains(line), "{usda}");
    for (v, needle) in [(0, "predates"), (2, "newer Shapewright")] {
        let text = usda.replace(
            line,
            &format!("custom uniform int shapewright:formatVersion = {v}"),
        );
        let err = load_from_str(&text, LoadOptions::default()).unwrap_err();
        assert!(
            matches!(err, LoadError::UnsupportedVersion { found, .. } if found == v),
            "{err}"
        );
        let msg = err.to_string();
        assert!(
            msg.contains(needle) && msg.contains("file format version"),
            "{msg}"
        );
    }
    let op_line = "custom uniform int shapewright:opFormatVersion = 1";
    let text = usda.replace(
        op_line,
        "custom uniform int shapewright:opFormatVersion = 9",
    );
    let msg = load_from_str(&text, LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(msg.contains("op format version 9"), "{msg}");
    // Missing log: a plain USD file.
    let plain = usda.replace(
        "def Scope \"ShapewrightLog\"",
        "def Scope \"SomethingElse\"",
    );
    assert!(matches!(
        load_from_str(&plain, LoadOptions::default()),
        Err(LoadError::NotShapewright)
    ));
}

#[test]
fn moved_points_are_reported_and_refused_when_strict() {
    let (log, usda) = saved_edits();
    // Move one coordinate of the first point of object 2.
    let start = usda.find("def Xform \"Object_2\"").unwrap();
    let at = start + usda[start..].find("point3f[] points = [(").unwrap();
    let open = at + "point3f[] points = [(".len();
    let end = open + usda[open..].find(',').unwrap();
    let mut text = usda.clone();
    text.replace_range(open..end, "12.5");
    let loaded = load_from_str(&text, LoadOptions::default()).unwrap();
    assert_eq!(loaded.report.mismatches.len(), 1, "{}", loaded.report);
    assert!(matches!(
        loaded.report.mismatches[0],
        Mismatch::Points { id, max_deviation, .. } if id.0 == 2 && max_deviation > 1.0
    ));
    // The log is still trusted and loaded as saved.
    assert_eq!(
        loaded.log.document().content_hash(),
        log.document().content_hash()
    );
    let strict = LoadOptions {
        strict: true,
        ..Default::default()
    };
    match load_from_str(&text, strict) {
        Err(LoadError::Inconsistent(r)) => assert!(r.to_string().contains("object #2")),
        other => panic!("expected Inconsistent, got {other:?}"),
    }
}

#[test]
fn missing_extra_and_retopologized_meshes_are_reported() {
    let (_, usda) = saved_edits();
    // Object 3 renamed to an id the log does not have: object 3 is missing
    // and the prim is extra.
    let text = usda.replace(
        "custom uniform int shapewright:objectId = 3",
        "custom uniform int shapewright:objectId = 77",
    );
    let r = load_from_str(&text, LoadOptions::default()).unwrap().report;
    assert!(
        r.mismatches.contains(&Mismatch::MissingMesh {
            id: shapewright::doc::ObjectId(3)
        }),
        "{r}"
    );
    assert!(
        r.mismatches
            .iter()
            .any(|m| matches!(m, Mismatch::ExtraPrim { path } if path.contains("Object_77"))),
        "{r}"
    );
    // A face split differently: indices differ.
    let start =
        usda.find("int[] faceVertexIndices = [").unwrap() + "int[] faceVertexIndices = [".len();
    let end = start + usda[start..].find(',').unwrap();
    let mut text = usda.clone();
    text.replace_range(start..end, "5");
    let r = load_from_str(&text, LoadOptions::default()).unwrap().report;
    assert!(
        r.mismatches
            .iter()
            .any(|m| matches!(m, Mismatch::Topology { .. })),
        "{r}"
    );
}

#[test]
fn snapshot_disagreeing_with_history_is_reported() {
    let (log, usda) = saved_edits();
    // Change a recorded op's parameter: the snapshot (and meshes) no longer
    // follow from the history.
    let text = usda.replacen("\"size\":[0.3,0.3,0.3]", "\"size\":[0.3,0.3,0.31]", 1);
    assert_ne!(text, usda);
    let quick = load_from_str(&text, LoadOptions::default()).unwrap();
    assert!(
        quick.report.is_consistent(),
        "meshes still match the snapshot"
    );
    let deep = load_from_str(&text, verify()).unwrap();
    assert!(
        deep.report
            .mismatches
            .iter()
            .any(|m| matches!(m, Mismatch::History { .. })),
        "{}",
        deep.report
    );
    assert_eq!(deep.log.len(), log.len());
}

#[test]
fn a_file_without_snapshot_is_rebuilt_by_replay() {
    let (log, usda) = saved_edits();
    let start = usda
        .find("custom uniform string shapewright:snapshot")
        .unwrap();
    let end = start + usda[start..].find('\n').unwrap();
    let mut text = usda.clone();
    text.replace_range(start..end, "");
    let loaded = load_from_str(&text, LoadOptions::default()).unwrap();
    assert!(loaded.replayed);
    assert_eq!(
        loaded.log.document().content_hash(),
        log.document().content_hash()
    );
    assert!(loaded.report.is_consistent(), "{}", loaded.report);
}

#[test]
fn truncated_log_is_an_error_not_a_shorter_history() {
    let (log, usda) = saved_edits();
    let n = log.len();
    let text = usda.replace(
        &format!("custom uniform int shapewright:opCount = {n}"),
        &format!("custom uniform int shapewright:opCount = {}", n + 1),
    );
    assert_ne!(text, usda, "opCount line present");
    let msg = load_from_str(&text, LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(msg.contains("opCount"), "{msg}");
}

#[test]
fn save_file_and_load_file() {
    let dir = common::scratch("files");
    let (log, _) = saved_edits();
    let path = dir.join("scene.usda");
    save_file(&path, &log, &SaveOptions::default()).unwrap();
    let loaded = load_file(&path, LoadOptions::default()).unwrap();
    assert_eq!(loaded.log.ops(), log.ops());
    // No temp files left behind.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
    let err = load_file(&dir.join("missing.usda"), LoadOptions::default()).unwrap_err();
    assert!(matches!(err, LoadError::Io { .. }));
}
