//! The GC ops' time budget (issue 37): no accepted GC op runs longer than
//! `gc::budget::MAX_SECONDS` on this machine, a refusal comes at once and
//! says what it estimated, and the estimate is right: an edit sized so
//! that its estimate is just under the limit runs within it (CPU seconds
//! of the whole process; tests here run one at a time).
//!
//! The union's work is in `manifold-rust`, a dependency, optimized in
//! every profile; the core's own share (meshing) runs at `opt-level = 1`
//! here, so a run may take [`BUILD_FACTOR`] times the release build's.
//! `calibrate` (ignored; `cargo test --release -p shapewright --test
//! timed gc_time::calibrate -- --ignored --nocapture`) prints the estimate and
//! the measured time of the edits the constants come from.

use crate::common;

use common::timed;
use shapewright::budget::OverBudget;
use shapewright::doc::{LogError, ObjectKind, Op, OpError, OpLog};
use shapewright::gc::budget::{edit_seconds, MAX_SECONDS};
use shapewright::gc::{GcAssembly, GcError};
use shapewright::math::fm::DetMath as _;

/// How much slower this build runs a GC op than the release build the
/// constants are for.
const BUILD_FACTOR: f64 = if cfg!(debug_assertions) { 1.5 } else { 1.0 };

fn ops(name: &str) -> Vec<serde_json::Value> {
    common::data(name)
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn op(v: &serde_json::Value) -> Op {
    serde_json::from_value(v.clone()).unwrap()
}

fn assembly(log: &OpLog) -> GcAssembly {
    match &log.document().objects().next().unwrap().1.kind {
        ObjectKind::GcAssembly(a) => a.clone(),
        _ => unreachable!(),
    }
}

/// The mug's body (a container) at `r` × `r` segments.
fn mug_body(r: u32) -> serde_json::Value {
    let mut body = ops("mug.jsonl")[0].clone();
    body["resolution"] = serde_json::json!({"u": r, "v": r});
    body
}

/// The mug's handle (its second op).
fn handle() -> Op {
    op(&ops("mug.jsonl")[1])
}

/// The estimate of adding the handle to the mug's body at `r` (the body
/// built as `gc_create` builds it, not applied: applying meshes and
/// unites it, which the estimate does not need).
fn handle_estimate(r: u32) -> f64 {
    let Op::GcCreate(create) = op(&mug_body(r)) else {
        unreachable!()
    };
    let before = GcAssembly::single(create.0.build().unwrap());
    let Op::GcAddChild(edit) = handle() else {
        unreachable!()
    };
    let mut after = before.clone();
    edit.apply_to(&mut after).unwrap();
    edit_seconds(Some(&before), &after).unwrap()
}

/// The log with the mug's body at `r`, the handle, and its estimate,
/// checked against the estimate from the applied body.
fn body_and_handle_estimate(r: u32) -> (OpLog, Op, f64) {
    let mut log = OpLog::new();
    log.apply(op(&mug_body(r))).unwrap();
    let before = assembly(&log);
    let Op::GcAddChild(edit) = handle() else {
        unreachable!()
    };
    let mut after = before.clone();
    edit.apply_to(&mut after).unwrap();
    let est = edit_seconds(Some(&before), &after).unwrap();
    assert_eq!(est, handle_estimate(r));
    (log, handle(), est)
}

/// The largest body resolution whose handle is estimated under `limit`.
fn resolution_under(limit: f64) -> u32 {
    let (mut lo, mut hi) = (64u32, 1024u32);
    while hi - lo > 4 {
        let mid = (lo + hi) / 2;
        if handle_estimate(mid) < limit {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Issue 37: "no accepted op runs longer than 10 s on this machine ...
/// a test per op kind compares the estimate with a measured run at the
/// limit". A handle added to a mug body just fine enough to be estimated
/// at the limit runs within it, and not far under (the estimate is
/// neither unsafe nor so pessimistic it refuses what would be quick).
/// Before the estimate, a body at 724 × 724 took the same edit to 10.1 s
/// and 1000 × 1000 to 20 s, both accepted.
#[test]
fn an_edit_at_the_time_limit_runs_within_it() {
    let _serial = crate::serial();
    let r = resolution_under(MAX_SECONDS);
    let (mut log, add, est) = body_and_handle_estimate(r);
    let (res, cpu, wall) = timed(|| log.apply(add));
    res.unwrap();
    println!(
        "body at {r} x {r}: adding the handle estimated {est:.2} s, ran {cpu:.2} s CPU ({wall:.2} s wall) in a build {BUILD_FACTOR}x slower than release"
    );
    assert!(
        cpu <= MAX_SECONDS * BUILD_FACTOR,
        "ran {cpu:.1} s CPU, over the limit ({MAX_SECONDS} s, x{BUILD_FACTOR} for this build)"
    );
    assert!(
        cpu * 3.0 >= est,
        "ran {cpu:.2} s, the estimate {est:.2} s is far too pessimistic"
    );
}

/// The same edit on a body a little finer is refused at once, naming its
/// estimate over the limit, and leaves the document as it was.
#[test]
fn an_edit_over_the_time_limit_is_refused_at_once() {
    let _serial = crate::serial();
    let r = resolution_under(MAX_SECONDS) + 8;
    let (mut log, add, est) = body_and_handle_estimate(r);
    assert!(est > MAX_SECONDS);
    let hash = log.document().content_hash();
    let (res, cpu, _) = timed(|| log.apply(add));
    let e = res.expect_err("over the limit");
    println!("body at {r} x {r}: refused in {cpu:.2} s CPU: {e}");
    match &e {
        LogError::Op(OpError::Gc(GcError::OverBudget(OverBudget {
            parameter,
            estimate,
            limit,
            ..
        }))) => {
            assert_eq!(parameter, "parts");
            assert!(*estimate > *limit && *limit == MAX_SECONDS, "{e}");
            assert!(e.to_string().contains("over the limit of 10.00"), "{e}");
        }
        _ => panic!("{e}"),
    }
    assert!(cpu < 1.0 * BUILD_FACTOR, "refused after {cpu:.2} s");
    assert_eq!(log.document().content_hash(), hash);
}

/// Issue 37's abuse sweep: 64 sections of distinct 4,096-point loops were
/// fitted for 17 s before the skin's budget refused them. The fits are
/// sparse now, and the budget refuses once the profiles fitted so far ask
/// for too much.
#[test]
fn many_long_point_profiles_are_refused_at_once() {
    let _serial = crate::serial();
    let mut gc = mug_body(96);
    let n = 4096;
    gc["sections"] = (0..64)
        .map(|i| {
            let pts: Vec<[f64; 2]> = (0..n)
                .map(|j| {
                    let a = std::f64::consts::TAU * j as f64 / n as f64;
                    let r = 0.04 * (1.0 + 0.1 * (7.0 * a + i as f64).fsin());
                    [r * a.fcos(), r * a.fsin()]
                })
                .collect();
            serde_json::json!({"profile": {"template": "points", "points": pts}, "v": i as f64 / 63.0})
        })
        .collect();
    let mut log = OpLog::new();
    let (res, cpu, _) = timed(|| log.apply(op(&gc)));
    let e = res.expect_err("over the skin's budget");
    println!("refused in {cpu:.2} s CPU: {e}");
    assert!(e.to_string().contains("skinning work"), "{e}");
    assert!(cpu < 2.0 * BUILD_FACTOR, "refused after {cpu:.2} s");
}

/// Every example the project ships is far under the limit.
#[test]
fn the_examples_are_far_under_the_limit() {
    let _serial = crate::serial();
    for name in [
        "mug.jsonl",
        "teapot.jsonl",
        "chair.jsonl",
        "table.jsonl",
        "rack.jsonl",
    ] {
        let mut log = OpLog::new();
        let mut worst: f64 = 0.0;
        for o in ops(name) {
            let before = log
                .document()
                .objects()
                .next()
                .and_then(|(_, obj)| match &obj.kind {
                    ObjectKind::GcAssembly(a) => Some(a.clone()),
                    _ => None,
                });
            log.apply(op(&o)).unwrap();
            let after = assembly(&log);
            worst = worst.max(edit_seconds(before.as_ref(), &after).unwrap());
        }
        println!("{name}: the slowest op is estimated at {worst:.3} s");
        assert!(worst < MAX_SECONDS / 5.0, "{name}: {worst} s");
    }
}

/// Prints, for the edits the constants were fitted to, the estimate and
/// the measured CPU time: a body created and a handle added at 256 to
/// 724 segments, and every part of the chair, teapot and rack set to 128
/// and 256 segments one op at a time (the last op re-unites everything).
#[test]
#[ignore]
fn calibrate() {
    let _serial = crate::serial();
    for r in [256u32, 512, 724] {
        let mut log = OpLog::new();
        let create = op(&mug_body(r));
        let (res, cpu, _) = timed(|| log.apply(create));
        res.unwrap();
        let est = edit_seconds(None, &assembly(&log)).unwrap();
        println!("mug body {r}: create estimated {est:.2} s, ran {cpu:.2} s CPU");
        let (mut log, add, est) = body_and_handle_estimate(r);
        let (res, cpu, _) = timed(|| log.apply(add));
        let outcome = res.map_or_else(|e| e.to_string(), |_| "ok".into());
        println!("mug body {r}: handle estimated {est:.2} s, ran {cpu:.2} s CPU: {outcome}");
    }
    for name in ["chair.jsonl", "teapot.jsonl", "rack.jsonl"] {
        for r in [128u32, 256] {
            let mut log = OpLog::new();
            for o in ops(name) {
                log.apply(op(&o)).unwrap();
            }
            let parts = assembly(&log).parts.len();
            for part in (0..parts).rev() {
                let before = assembly(&log);
                let set = serde_json::json!({"op": "gc_set_resolution", "id": 1, "part": part, "resolution": {"u": r, "v": r}});
                let (res, cpu, _) = timed(|| log.apply(op(&set)));
                if let Err(e) = res {
                    println!("{name} {r}: part {part}: {e}");
                    break;
                }
                let est = edit_seconds(Some(&before), &assembly(&log)).unwrap();
                println!("{name} {r}: part {part} estimated {est:.2} s, ran {cpu:.2} s CPU");
            }
        }
    }
}
