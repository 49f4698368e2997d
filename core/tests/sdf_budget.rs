//! The SDF budgets refuse at once (issues 33 and 37): an update whose
//! queued operands would take longer than the time limit to fuse is
//! refused before any of the work, with a message stating the estimate
//! and the limit, and the document is unchanged. Before, the estimate
//! counted memory only and only after the grid was built, so such a queue
//! was fused in full (a chain of fused copies was refused after 47 s).

mod common;

use std::time::{Duration, Instant};

use common::run;
use shapewright::doc::{LogError, Op, OpError};
use shapewright::sdf::budget::TIME_LIMIT_SECONDS;
use shapewright::sdf::SdfError;

fn op(json: &str) -> Op {
    serde_json::from_str(json).unwrap_or_else(|e| panic!("{json}: {e}"))
}

/// Six spheres 5 m across queued side by side in a 1 cm volume: each is
/// accepted alone (estimated 2.3 s, 117 MiB), together they are within
/// the memory budget but over the 10 s limit.
fn six_spheres() -> String {
    let mut s = String::from("{\"op\": \"sdf_create\", \"step\": 0.01}\n");
    for i in 0..6 {
        s.push_str(&format!(
            "{{\"op\": \"sdf_add_operand\", \"volume\": 1, \"component\": {{\"kind\": \"solid\", \"shape\": {{\"kind\": \"sphere\", \"radius\": 2.5}}}}, \"csg\": \"union\", \"transform\": {{\"translate\": [{}, 0, 0]}}}}\n",
            6.0 * i as f64
        ));
    }
    s
}

#[test]
fn an_update_over_the_time_limit_is_refused_at_once() {
    let mut log = run(&six_spheres());
    let before = log.document().content_hash();
    let t0 = Instant::now();
    let e = log
        .apply(op(r#"{"op": "sdf_update", "volume": 1}"#))
        .unwrap_err();
    let took = t0.elapsed();
    let LogError::Op(OpError::Sdf(e)) = e else {
        panic!("not an SDF error: {e:?}")
    };
    let text = e.to_string();
    let SdfError::TooSlow { seconds, limit, .. } = e else {
        panic!("{text}")
    };
    assert_eq!(limit, TIME_LIMIT_SECONDS);
    assert!(seconds > limit, "{text}");
    // The message states both numbers as they are.
    assert!(
        text.contains(&format!("{seconds:.1} s")) && text.contains(&format!("{limit} s limit")),
        "{text}"
    );
    assert!(took < Duration::from_secs(2), "refused after {took:?}");
    assert_eq!(log.document().content_hash(), before);
}
