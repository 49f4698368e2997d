//! Op log costs: apply, replay, and undo+redo for 1k- and 10k-op logs.
//! Undo restores the nearest checkpoint and replays a bounded tail, so its
//! cost must not grow with the log length.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use shapewright::doc::{AddSolid, ObjectId, Op, OpLog, TransformBy};
use shapewright::math::Transform;
use shapewright::solid::SolidShape;

/// A session: 10 spheres, then small moves round-robin over them.
fn session(len: usize) -> Vec<Op> {
    (0..len)
        .map(|i| {
            if i < 10 {
                Op::AddSolid(AddSolid {
                    shape: SolidShape::Sphere { radius: 0.1 },
                    segments: 16,
                    transform: Transform::translation([i as f64 * 0.3, 0.0, 0.0]),
                })
            } else {
                Op::TransformBy(TransformBy {
                    id: ObjectId((i % 10) as u32 + 1),
                    transform: Transform::translation([0.001, 0.0, 0.0005]),
                })
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("oplog");
    g.sample_size(10);
    g.warm_up_time(std::time::Duration::from_secs(1));
    g.measurement_time(std::time::Duration::from_secs(3));
    for len in [1_000usize, 10_000] {
        let ops = session(len);
        g.bench_with_input(BenchmarkId::new("apply_all", len), &ops, |b, ops| {
            b.iter_batched(
                || ops.clone(),
                |ops| {
                    let mut log = OpLog::new();
                    for op in ops {
                        log.apply(op).unwrap();
                    }
                    log
                },
                BatchSize::LargeInput,
            )
        });
        g.bench_with_input(BenchmarkId::new("replay", len), &ops, |b, ops| {
            b.iter_batched(
                || ops.clone(),
                |ops| OpLog::replay(ops, len).unwrap(),
                BatchSize::LargeInput,
            )
        });
        let mut log = OpLog::replay(ops.clone(), len).unwrap();
        g.bench_function(BenchmarkId::new("undo_redo", len), |b| {
            b.iter(|| {
                log.undo().unwrap();
                log.redo().unwrap();
            })
        });
        let mut log = OpLog::replay(ops.clone(), len).unwrap();
        g.bench_function(BenchmarkId::new("undo_100_then_redo_100", len), |b| {
            b.iter(|| {
                for _ in 0..100 {
                    log.undo().unwrap();
                }
                for _ in 0..100 {
                    log.redo().unwrap();
                }
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
