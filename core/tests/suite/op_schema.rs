//! The op schema against the ops themselves: every op is described, with
//! docs; its ranges are what the core enforces at the door; every op of
//! every fixture round-trips through a `.jsonl` line; the script format's
//! version key collides with no op field.

use std::path::Path;

use serde_json::{json, Value};
use shapewright::doc::schema::{check_op, op_schema, MAX_LENGTH};
use shapewright::doc::*;

fn schema() -> Value {
    op_schema()
}

fn fixture_ops() -> Vec<Op> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    let mut ops = Vec::new();
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".jsonl") && !n.ends_with(".trace.jsonl"))
        .collect();
    names.sort();
    for n in names {
        let text = std::fs::read_to_string(dir.join(&n)).unwrap();
        for l in parse_script(&text).unwrap() {
            if let ScriptCommand::Op(op) = l.command {
                ops.push(op);
            }
        }
    }
    ops
}

#[test]
fn every_op_is_described_in_table_order_with_docs() {
    let s = schema();
    let ops = s["ops"].as_array().unwrap();
    let names: Vec<&str> = ops.iter().map(|o| o["name"].as_str().unwrap()).collect();
    assert_eq!(names, OP_NAMES);
    for o in ops {
        let name = o["name"].as_str().unwrap();
        assert!(
            o["doc"].as_str().is_some_and(|d| d.len() > 10),
            "{name} has no doc: {o}"
        );
        assert!(
            matches!(
                o["kind"].as_str().unwrap(),
                "document"
                    | "session"
                    | "solid"
                    | "gc_assembly"
                    | "sdf_volume"
                    | "curve_network"
                    | "sculpt_mesh"
            ),
            "{name}"
        );
        for f in o["fields"].as_array().unwrap() {
            assert!(
                f["doc"].as_str().is_some_and(|d| !d.is_empty()),
                "{name}.{} has no doc",
                f["name"]
            );
        }
    }
}

#[test]
fn edits_name_their_object_first_and_typed_indices_are_marked() {
    let s = schema();
    for o in s["ops"].as_array().unwrap() {
        let name = o["name"].as_str().unwrap();
        let kind = o["kind"].as_str().unwrap();
        let fields = o["fields"].as_array().unwrap();
        let creates = name.ends_with("_create") || name == "add_solid";
        // Ops on one object name it first; document-wide and session ops
        // (reserve_ids, written by shared sessions) name none.
        if kind != "document" && kind != "session" && !creates {
            let first = &fields[0];
            assert_eq!(first["ref"], "object", "{name}: {first}");
            assert_eq!(first["required"], true, "{name}");
        }
        for f in fields {
            let fname = f["name"].as_str().unwrap();
            if matches!(
                fname,
                "part" | "parent" | "section" | "curve" | "patch" | "operand"
            ) {
                assert!(
                    f["ref"].is_string(),
                    "{name}.{fname} is an untyped index: {f}"
                );
            }
        }
    }
}

#[test]
fn the_version_key_is_no_op_field() {
    let s = schema();
    let key = s["version_key"].as_str().unwrap();
    for o in s["ops"].as_array().unwrap() {
        for f in o["fields"].as_array().unwrap() {
            assert_ne!(f["name"], key, "{}", o["name"]);
        }
    }
}

#[test]
fn ops_with_a_field_v_parse_and_old_version_lines_still_load() {
    let text = r#"{"op":"gc_create","spine":[[0,0,0],[0,0,0.1]],"plane_normal":[1,0,0],"sections":[{"profile":{"template":"circle","radius":0.02},"v":0},{"profile":{"template":"circle","radius":0.02},"v":1}],"v":1}
{"op":"gc_insert_section","id":1,"v":0.5}
{"op":"gc_shift","id":1,"section":1,"v":0.4,"op_version":1}
{"op":"undo"}"#;
    let lines = parse_script(text).unwrap();
    let mut log = OpLog::new();
    run_script(&mut log, &lines).unwrap();
    assert_eq!(log.len(), 3);
    match &log.ops()[1] {
        Op::GcInsertSection(e) => assert_eq!(e.edit.v, 0.5),
        other => panic!("{other:?}"),
    }
    let newer = r#"{"op":"gc_shift","id":1,"section":1,"v":0.4,"op_version":99}"#;
    assert!(matches!(
        parse_script(newer).unwrap_err().kind,
        ScriptErrorKind::UnsupportedVersion(99)
    ));
}

#[test]
fn every_fixture_op_round_trips_through_a_jsonl_line() {
    let ops = fixture_ops();
    assert!(ops.len() > 100, "{}", ops.len());
    for op in ops {
        let line = serde_json::to_string(&op).unwrap();
        let back = parse_script(&line).unwrap_or_else(|e| panic!("{line}: {e}"));
        assert_eq!(back[0].command, ScriptCommand::Op(op.clone()), "{line}");
        check_op(&op).unwrap_or_else(|e| panic!("{line}: {e}"));
    }
}

#[test]
fn the_door_refuses_non_finite_and_out_of_range_values_naming_the_field() {
    let sphere = |r: f64| {
        Op::AddSolid(AddSolid {
            shape: shapewright::solid::SolidShape::Sphere { radius: r },
            segments: 16,
            transform: Default::default(),
        })
    };
    let mut log = OpLog::new();
    for (r, needle) in [
        (f64::NAN, "not a finite number"),
        (f64::INFINITY, "not a finite number"),
        (f64::MAX, "farther than"),
        (3.4e38, "farther than"),
        (1e39, "farther than"),
    ] {
        let err = log.apply(sphere(r)).unwrap_err().to_string();
        assert!(err.contains("shape.radius"), "{r}: {err}");
        assert!(err.contains(needle), "{r}: {err}");
    }
    for r in [0.0, -1.0] {
        let err = log.apply(sphere(r)).unwrap_err().to_string();
        assert!(err.contains("radius"), "{r}: {err}");
    }
    assert_eq!(log.len(), 0);
    log.apply(sphere(MAX_LENGTH)).unwrap();
    // Deep fields: a NaN sample inside a stroke path names its index.
    let mut op: Value = json!({"op":"curve_network_create","resolution":8,"surface_n":4});
    log.apply(serde_json::from_value(op.clone()).unwrap())
        .unwrap();
    op = json!({"op":"curve_draw","id":2,"samples":[[0,0,0],[0.1,0,0],[0.2,0,0],[0.3,0,0]],
                "fit":{"mode":"interpolate"},"resample":null,"snap_tol":0.001});
    let mut draw: Op = serde_json::from_value(op).unwrap();
    if let Op::CurveDraw(e) = &mut draw {
        e.edit.samples[2][1] = f64::NAN;
    }
    let err = log.apply(draw).unwrap_err().to_string();
    assert!(err.contains("samples[2][1]"), "{err}");
}

#[test]
fn declared_ranges_are_enforced_at_their_bounds() {
    // Along every fixture script: for each op with a numeric field that
    // declares a bound, the same op with the value just past the bound is
    // refused at that point of the script (by the door or by the geometry
    // code's own typed error), while the original applies. So a host that
    // offers the declared range never offers a value the core refuses at
    // the bound, and never lets through one past it.
    let s = schema();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    let mut checked = 0;
    for name in [
        "primitives.jsonl",
        "mug.jsonl",
        "csg_cup.jsonl",
        "curve_network.jsonl",
        "chair.jsonl",
    ] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let mut log = OpLog::new();
        for l in parse_script(&text).unwrap() {
            let ScriptCommand::Op(op) = l.command else {
                continue;
            };
            let v = serde_json::to_value(&op).unwrap();
            let desc = s["ops"]
                .as_array()
                .unwrap()
                .iter()
                .find(|o| o["name"] == op.name())
                .unwrap();
            for f in desc["fields"].as_array().unwrap() {
                let fname = f["name"].as_str().unwrap();
                if !v[fname].is_number() {
                    continue;
                }
                let mut bads = Vec::new();
                if let Some(m) = f["maximum"].as_f64() {
                    bads.push(if v[fname].is_f64() {
                        m * 1.001 + 1e-9
                    } else {
                        m + 1.0
                    });
                }
                if let Some(m) = f["minimum"].as_f64() {
                    bads.push(if v[fname].is_f64() { m - 1e-3 } else { m - 1.0 });
                }
                if let Some(m) = f["exclusiveMinimum"].as_f64() {
                    bads.push(m);
                }
                for bad in bads {
                    let mut w = v.clone();
                    w[fname] = json!(bad);
                    let Ok(op2) = serde_json::from_value::<Op>(w) else {
                        continue; // an unsigned field cannot hold it at all
                    };
                    let mut trial = log.clone();
                    assert!(
                        trial.apply(op2).is_err(),
                        "{name}:{}: {}.{fname} = {bad} was accepted",
                        l.line,
                        op.name()
                    );
                    checked += 1;
                }
            }
            log.apply(op).unwrap();
        }
    }
    assert!(checked >= 10, "only {checked} bounds exercised");
}
