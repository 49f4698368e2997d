//! The resource-abuse reproducers of issue 22 (`tests/data/abuse/`, and
//! the big ones `make_big.py` writes, built here) through the op log: each
//! is a typed error that names the parameter and the limit, refused before
//! the work (these used to abort on allocation or run past a minute), and
//! the document is left as it was.

use shapewright::math::fm::DetMath as _;
use std::path::PathBuf;

use shapewright::budget::OverBudget;
use shapewright::doc::{parse_script, LogError, OpError, OpLog, ScriptCommand};
use shapewright::gc::budget::{MAX_GRID_POINTS, MAX_SECTIONS};
use shapewright::gc::GcError;
use shapewright::interact::trace::{replay, Trace};
use shapewright::sculpt::budget::MAX_FRAME_TRIANGLES;
use shapewright::sculpt::SculptError;
use shapewright::styling::StylingError;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data")
        .join(name)
}

/// Applies a script; returns the log and the first refused op's error.
fn apply(text: &str) -> (OpLog, Option<OpError>) {
    let mut log = OpLog::new();
    for l in parse_script(text).unwrap() {
        let ScriptCommand::Op(op) = l.command else {
            continue;
        };
        match log.apply(op) {
            Ok(_) => {}
            Err(LogError::Op(e)) => return (log, Some(e)),
            Err(e) => panic!("line {}: {e}", l.line),
        }
    }
    (log, None)
}

fn apply_file(name: &str) -> (OpLog, OpError) {
    let text = std::fs::read_to_string(data(name)).unwrap();
    let (log, e) = apply(&text);
    (log, e.unwrap_or_else(|| panic!("{name} was accepted")))
}

fn mug_gc(sections: usize, resolution: Option<(u32, u32)>) -> String {
    let text = std::fs::read_to_string(data("mug.jsonl")).unwrap();
    let line = text.lines().find(|l| l.contains("\"gc_create\"")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
    v["sections"] = (0..sections)
        .map(|i| {
            serde_json::json!({
                "profile": {"template": "circle", "radius": 0.04},
                "v": i as f64 / (sections - 1) as f64,
            })
        })
        .collect();
    if let Some((u, w)) = resolution {
        v["resolution"] = serde_json::json!({"u": u, "v": w});
    }
    v.to_string()
}

#[test]
fn gc_resolution_4096_is_refused_naming_the_resolution() {
    let (log, e) = apply_file("abuse/gc_resolution_4096.jsonl");
    let OpError::Gc(GcError::OverBudget(OverBudget {
        parameter,
        estimate,
        limit,
        ..
    })) = &e
    else {
        panic!("{e}")
    };
    let (estimate, limit) = (*estimate, *limit);
    assert_eq!(parameter, "resolution");
    assert_eq!(limit, MAX_GRID_POINTS);
    assert!(estimate > 4096.0 * 4096.0, "{estimate}");
    assert!(log.document().is_empty());
    assert!(e.to_string().contains("resolution"), "{e}");
    // One axis at 4096 stays accepted (a long cable).
    let (log, e) = apply(&mug_gc(4, Some((4, 4096))));
    assert!(e.is_none(), "{e:?}");
    assert_eq!(log.len(), 1);
}

#[test]
fn gc_section_counts_past_the_limit_are_refused_before_skinning() {
    // 20,000 sections asked for 3 GB and minutes (1e6 for 8 TB).
    for n in [MAX_SECTIONS + 1, 20_000] {
        let (log, e) = apply(&mug_gc(n, None));
        let Some(OpError::Gc(GcError::OverBudget(OverBudget {
            parameter,
            estimate,
            ..
        }))) = e
        else {
            panic!("{n} sections: {e:?}")
        };
        assert_eq!(parameter, "sections");
        assert_eq!(estimate, n as f64);
        assert!(log.document().is_empty());
    }
    let (log, e) = apply(&mug_gc(MAX_SECTIONS, None));
    assert!(e.is_none(), "{e:?}");
    assert_eq!(log.len(), 1);
    // Inserting one more section is refused the same way.
    let (_, e) = apply(&format!(
        "{}\n{{\"op\":\"gc_insert_section\",\"id\":1,\"part\":0,\"v\":0.5001}}\n",
        mug_gc(MAX_SECTIONS, None)
    ));
    assert!(
        matches!(
            &e,
            Some(OpError::Gc(GcError::OverBudget(OverBudget { parameter, .. })))
                if parameter == "sections"
        ),
        "{e:?}"
    );
}

#[test]
fn gc_skinning_work_of_many_distinct_profiles_is_bounded() {
    // 100 sections, each a distinct 300-point loop: the compatible sections
    // would have 120,000 control columns, each a dense 102² solve.
    let text = std::fs::read_to_string(data("mug.jsonl")).unwrap();
    let line = text.lines().find(|l| l.contains("\"gc_create\"")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
    let n = 100;
    v["sections"] = (0..n)
        .map(|i| {
            let pts: Vec<[f64; 2]> = (0..300)
                .map(|j| {
                    let a = std::f64::consts::TAU * j as f64 / 300.0;
                    let r = 0.04 * (1.0 + 0.1 * (7.0 * a + i as f64).fsin());
                    [r * a.fcos(), r * a.fsin()]
                })
                .collect();
            serde_json::json!({"profile": {"template": "points", "points": pts}, "v": i as f64 / (n - 1) as f64})
        })
        .collect();
    let (_, e) = apply(&v.to_string());
    assert!(
        matches!(
            &e,
            Some(OpError::Gc(GcError::OverBudget(OverBudget {
                parameter,
                what,
                ..
            }))) if parameter == "sections" && what.contains("skinning")
        ),
        "{e:?}"
    );
}

fn sculpt_error(e: OpError) -> SculptError {
    match e {
        OpError::Sculpt(s) => s,
        e => panic!("not a sculpt error: {e}"),
    }
}

#[test]
fn sculpt_strokes_that_would_refine_without_bound_are_refused() {
    // max_edge_rel 1e-4: GBs and minutes before; below the declared floor.
    let (log, e) = apply_file("abuse/sculpt_small_max_edge.jsonl");
    assert!(
        matches!(sculpt_error(e), SculptError::OutOfRange { ref field, .. } if field == "max_edge_rel")
    );
    assert_eq!(log.len(), 1);
    // A sample 100 m away: the stretched band would be ~1e8 triangles.
    let (log, e) = apply_file("abuse/sculpt_far_sample.jsonl");
    let SculptError::OverBudget(OverBudget {
        parameter: field,
        estimate,
        limit,
        ..
    }) = sculpt_error(e)
    else {
        panic!()
    };
    assert_eq!(field, "samples[15].position");
    assert_eq!(limit, MAX_FRAME_TRIANGLES);
    assert!(estimate > 1e7, "{estimate}");
    assert_eq!(log.len(), 1);
    // At the floor, a large brush reach is still refused by the estimate,
    // and explode with a huge delta names the delta.
    let text = std::fs::read_to_string(data("abuse/sculpt_small_max_edge.jsonl")).unwrap();
    let floor = text.replace("\"max_edge_rel\":0.0001", "\"max_edge_rel\":0.001");
    let (_, e) = apply(&floor);
    assert!(
        matches!(sculpt_error(e.unwrap()), SculptError::OverBudget(OverBudget { ref parameter, .. }) if parameter == "max_edge_rel")
    );
    let far = std::fs::read_to_string(data("abuse/sculpt_far_sample.jsonl")).unwrap();
    let explode = far.replace(
        "\"warp\":{\"kind\":\"drag\"}",
        "\"warp\":{\"kind\":\"explode\",\"delta\":1000000.0}",
    );
    assert_ne!(explode, far);
    let (_, e) = apply(&explode);
    assert!(
        matches!(sculpt_error(e.unwrap()), SculptError::OverBudget(OverBudget { ref parameter, .. }) if parameter == "warp.delta")
    );
    // The same stroke with its last sample 1 m away is a bounded success
    // (it pulls the surface through itself: flagged, not refused, since
    // this test is about the budget, not the fold).
    let near = far.replace("[100.0,0,0]", "[1.0,0,0]");
    assert_ne!(near, far);
    let flag = "{\"op\":\"set_self_intersection_policy\",\"policy\":\"flag\"}\n";
    let (log, e) = apply(&format!("{flag}{near}"));
    assert!(e.is_none(), "{e:?}");
    assert_eq!(log.len(), 3);
}

#[test]
fn curve_draw_abuse_is_refused_before_resampling() {
    for name in [
        "abuse/curve_draw_resample_tiny.jsonl",
        "abuse/curve_draw_far_sample.jsonl",
        "abuse/styling_curve_huge_sample.jsonl",
    ] {
        let (log, e) = apply_file(name);
        let named = match &e {
            OpError::Styling(StylingError::OverBudget(OverBudget { parameter, .. })) => {
                *parameter == "resample"
            }
            OpError::BadField { field, .. } => field.starts_with("samples["),
            _ => false,
        };
        assert!(named, "{name}: {e}");
        assert_eq!(log.len(), 1, "{name}");
    }
    // 1e5 samples (80 GB for the dense fit before): over the fit points.
    let text = std::fs::read_to_string(data("curve_network.jsonl")).unwrap();
    let mut ops = parse_script(&text).unwrap().into_iter();
    let ScriptCommand::Op(create) = ops.next().unwrap().command else {
        panic!()
    };
    let ring: Vec<[f64; 3]> = (0..100_000)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 1e5;
            [0.1 * a.fcos(), 0.1 * a.fsin(), 0.0]
        })
        .collect();
    let draw = serde_json::json!({
        "op": "curve_draw", "id": 1, "samples": ring, "fit": {"mode": "interpolate"},
        "resample": null, "snap_tol": 0.002
    });
    let script = format!("{}\n{}\n", serde_json::to_string(&create).unwrap(), draw);
    let (log, e) = apply(&script);
    assert!(
        matches!(
            &e,
            Some(OpError::Styling(StylingError::OverBudget(OverBudget { parameter, .. })))
                if parameter == "samples"
        ),
        "{e:?}"
    );
    assert_eq!(log.len(), 1);
}

#[test]
fn a_curve_trace_at_model_scale_1e_9_is_refused_stroke_by_stroke() {
    // The trace's strokes become 1e9 times longer in model space: 482 GB
    // asked for before; now every curve_draw is refused at the door.
    let text = std::fs::read_to_string(data("curve_network.trace.jsonl")).unwrap();
    let mut trace = Trace::from_jsonl(&text).unwrap();
    trace.header.model.scale = 1e-9;
    let r = replay(&trace).unwrap();
    let draws = r
        .commands
        .iter()
        .filter(|c| matches!(c, ScriptCommand::Op(op) if op.name() == "curve_draw"))
        .count();
    assert!(draws >= 12, "{draws}");
    let refused = r
        .rejected
        .iter()
        .filter(|(_, e)| {
            matches!(e, LogError::Op(OpError::BadField { op: "curve_draw", field, .. }) if field.starts_with("samples["))
        })
        .count();
    assert_eq!(refused, draws);
    assert_eq!(r.log.document().len(), 1);
}
