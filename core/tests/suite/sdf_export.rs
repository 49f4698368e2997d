//! SDF operands queued but not yet fused print (issue 33): every exit's
//! print path fuses a volume's queue as the next `sdf_update` would,
//! without changing the document, and places the result as the object
//! is; before, the queue was silently left out (a cup whose update was
//! never pressed exported as nothing).

use crate::common;

use common::{data, run};
use shapewright::doc::print_document;
use shapewright::doc::Op;
use shapewright::print::PrintSettings;

fn op(json: &str) -> Op {
    serde_json::from_str(json).unwrap_or_else(|e| panic!("{json}: {e}"))
}

/// The cup script without its final update (three queued operands).
fn queued_cup() -> String {
    data("csg_cup.jsonl")
        .lines()
        .filter(|l| !l.contains("sdf_update"))
        .map(|l| format!("{l}\n"))
        .collect()
}

#[test]
fn a_queued_cup_prints_as_the_updated_cup() {
    let queued = run(&queued_cup());
    let updated = run(&data("csg_cup.jsonl"));
    let hash = queued.document().content_hash();
    let a = print_document(queued.document(), &PrintSettings::default()).unwrap();
    let b = print_document(updated.document(), &PrintSettings::default()).unwrap();
    assert_eq!(a.mesh.positions, b.mesh.positions);
    assert_eq!(a.mesh.triangles, b.mesh.triangles);
    assert_eq!(a.report.checks.genus, Some(1));
    // Printing changed nothing.
    assert_eq!(queued.document().content_hash(), hash);
}

#[test]
fn queued_operands_after_an_update_print_placed_with_the_volume() {
    let mut log = run(&data("csg_cup.jsonl"));
    let one = print_document(log.document(), &PrintSettings::default()).unwrap();
    // A second cup queued beside the first (not fused), the volume moved.
    log.apply(op(r#"{"op":"sdf_copy_fused","volume":1,"name":"again","csg":"union","transform":{"translate":[0.4,0,0],"rotate":[0,0,0,1],"scale":[1,1,1]}}"#))
        .unwrap();
    log.apply(op(r#"{"op":"set_transform","id":1,"transform":{"translate":[0,0,0.5],"rotate":[0,0,0,1],"scale":[1,1,1]}}"#))
        .unwrap();
    let two = print_document(log.document(), &PrintSettings::default()).unwrap();
    assert_eq!(two.report.checks.components, 2);
    let ratio = two.report.checks.signed_volume / one.report.checks.signed_volume;
    assert!((ratio - 2.0).abs() < 0.02, "{ratio}");
    let (lo, hi) = two.mesh.bbox().unwrap();
    let (lo1, _) = one.mesh.bbox().unwrap();
    assert!((lo.z - (lo1.z + 0.5)).abs() < 1e-6, "{} vs {}", lo.z, lo1.z);
    assert!(hi.x > 0.5, "the copy is printed: {hi}");
}
