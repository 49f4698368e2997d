//! Criterion benches of the SDF system: one lazy update (fusion + one
//! extraction) of the paper's Cup and Chair at the default step. The peer
//! comparison (NumPy + scikit-image, fast-surface-nets, all steps, full
//! grids) is scripts/bench/sdf.py.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{criterion_group, criterion_main, Criterion};
use shapewright::doc::{parse_script, run_script, ObjectId, ObjectKind, OpLog};
use shapewright::sdf::SdfVolume;

/// The volume of a scene script with its fused operands moved back to
/// pending, so `updated()` redoes the whole update.
fn pending_volume(script: &str) -> SdfVolume {
    let mut log = OpLog::new();
    run_script(&mut log, &parse_script(script).expect("script")).expect("runs");
    let ObjectKind::SdfVolume(v) = &log.document().get(ObjectId(1)).expect("volume").kind else {
        panic!("object 1 is not a volume");
    };
    let mut fresh = SdfVolume::new(v.step).expect("step");
    fresh.pending = v.fused.clone();
    fresh
}

fn bench(c: &mut Criterion) {
    for (name, script) in [
        ("cup", include_str!("../../tests/data/csg_cup.jsonl")),
        ("chair", include_str!("../../tests/data/csg_chair.jsonl")),
    ] {
        let v = pending_volume(script);
        c.bench_function(&format!("sdf_update_{name}_step_0.01"), |b| {
            b.iter(|| v.updated().expect("update"))
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
