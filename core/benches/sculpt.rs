//! Warp-brush frame times: a 200-frame drag stroke on geodesic spheres of
//! about 150k and 500k vertices, p50 / p99 / max per frame (goal: p99 under
//! 11.1 ms, one 90 Hz frame, at 500k), plus the cost of the whole stroke as
//! one `sculpt_stroke` op (clone, index, frames, re-evaluation), then
//! Criterion measurements of single frames: an explode/collapse frame at
//! 150k and the bench stroke's frames, in order, at 2M vertices.
//!
//! Run: `cargo bench -p shapewright --bench sculpt`. The stroke is
//! `fixtures/sculpt_stroke.rs`; the 2M / 5M goal rows of the honest bench
//! (`scripts/bench/run_all.py`) time the same stroke in `perf_goals`.

use std::time::Instant;

use criterion::{black_box, Criterion};
use shapewright::doc::{Create, Edit, ObjectId, Op, OpLog};
use shapewright::math::{DQuat, DVec3};
use shapewright::sculpt::base::geodesic_sphere;
use shapewright::sculpt::stroke::{FrameInput, Sculptor};
use shapewright::sculpt::{BrushPose, HalfEdgeMesh, SculptBase, SculptCreate, SculptStroke, Warp};

#[path = "fixtures/sculpt_stroke.rs"]
mod stroke;
use stroke::{frame_input, pct, run_frames, samples, settings, Run, FRAMES};

/// Repetitions of the stroke; each frame's cost is deterministic, so the
/// per-frame minimum over repetitions filters out time spent preempted on
/// a loaded machine (reported beside the first run's raw times).
const REPS: usize = 3;

fn frame_times(n: u32) {
    let mesh = HalfEdgeMesh::from_trimesh(&geodesic_sphere(1.0, n), "base").unwrap();
    let verts = mesh.vertex_count();
    let s = settings(n);
    let smp = samples();
    let runs: Vec<Run> = (0..REPS).map(|_| run_frames(mesh.clone(), &s)).collect();
    for r in &runs[1..] {
        assert_eq!(r.sculptor.mesh(), runs[0].sculptor.mesh(), "runs differ");
    }
    let min_times: Vec<f64> = (0..FRAMES)
        .map(|i| {
            runs.iter()
                .map(|r| r.times[i])
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let Run {
        times,
        cpu,
        per_frame,
        sculptor: sc,
        index_ms,
    } = runs.into_iter().next().unwrap();
    let (moved, splits, collapses) = per_frame
        .iter()
        .fold((0, 0, 0), |a, f| (a.0 + f.0, a.1 + f.1, a.2 + f.2));
    let mut slowest: Vec<(usize, f64)> = times.iter().copied().enumerate().collect();
    slowest.sort_by(|a, b| b.1.total_cmp(&a.1));
    let slow: Vec<String> = slowest[..5]
        .iter()
        .map(|&(i, t)| {
            let (m, sp, co) = per_frame[i];
            format!("#{i} {t:.1} ms ({m} moved, {sp} splits, {co} collapses)")
        })
        .collect();
    println!("  slowest frames: {}", slow.join(", "));
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    let mut min_sorted = min_times.clone();
    min_sorted.sort_by(f64::total_cmp);
    println!(
        "  per-frame min over {REPS} runs: p50 {:.3} ms  p99 {:.3} ms  max {:.3} ms",
        pct(&min_sorted, 0.5),
        pct(&min_sorted, 0.99),
        min_sorted[FRAMES - 1]
    );
    println!(
        "sculpt frames n={n} verts={verts} -> {} after: p50 {:.3} ms  p99 {:.3} ms  max {:.3} ms  (index build {:.1} ms; {} vertex moves, {} splits, {} collapses over {FRAMES} frames)",
        sc.mesh().vertex_count(),
        pct(&sorted, 0.5),
        pct(&sorted, 0.99),
        sorted[sorted.len() - 1],
        index_ms,
        moved,
        splits,
        collapses
    );
    if cpu.len() == FRAMES {
        // schedstat advances in scheduler ticks, so only the mean is
        // meaningful per frame.
        println!(
            "  mean per frame: wall {:.3} ms, on-CPU {:.3} ms summed over threads (more than wall: parallel passes; less: waiting for a core)",
            times.iter().sum::<f64>() / FRAMES as f64,
            cpu.iter().sum::<f64>() / FRAMES as f64
        );
    }
    // The same stroke as one op through the log.
    let mut log = OpLog::new();
    log.apply(Op::SculptCreate(Create(SculptCreate {
        base: SculptBase::Mesh {
            positions: geodesic_sphere(1.0, n).positions,
            triangles: geodesic_sphere(1.0, n).triangles,
        },
        transform: Default::default(),
    })))
    .unwrap();
    let t = Instant::now();
    log.apply(Op::SculptStroke(Edit::new(
        ObjectId(1),
        SculptStroke {
            mirror: None,
            settings: s.clone(),
            samples: smp.clone(),
        },
    )))
    .unwrap();
    println!(
        "sculpt_stroke op n={n}: {:.1} ms for the {FRAMES}-frame stroke (clone + index + frames + mesh re-evaluation)",
        t.elapsed().as_secs_f64() * 1e3
    );
}

fn main() {
    // n = 122: 148,842 vertices; n = 224: 501,762 vertices.
    frame_times(122);
    frame_times(224);
    if std::env::var("SCULPT_FRAMES_ONLY").is_ok() {
        return;
    }
    let n = 122;
    let s = settings(n);
    let mut sc = Sculptor::new(
        HalfEdgeMesh::from_trimesh(&geodesic_sphere(1.0, n), "base").unwrap(),
        s.brush_size() + s.influence,
    );
    let size = s.brush_size();
    let smp = samples();
    let mut c = Criterion::default().sample_size(20).configure_from_args();
    let mut k = 0u64;
    c.bench_function("sculpt_explode_frame_150k", |b| {
        b.iter(|| {
            // Alternate explode and collapse so the mesh stays bounded.
            k += 1;
            let delta = if k.is_multiple_of(2) { 0.02 } else { -0.02 };
            let pose = BrushPose {
                position: DVec3::new(0.0, 0.0, 1.05),
                rotation: DQuat::IDENTITY,
                scale: 1.0,
            };
            black_box(sc.apply_frame(&FrameInput {
                shape: &s.brush,
                bound: s.brush.bound_radius(),
                prev: pose,
                pose,
                pressure: 1.0,
                influence: s.influence,
                falloff: s.falloff,
                warp: Warp::Explode { delta },
                max_len: s.max_edge_rel * size,
                min_len: s.min_edge_rel * size,
            }))
        })
    });
    // The bench stroke's frames at 2M vertices (issue 21's goal: p99 under
    // 11.1 ms), in stroke order: each iteration is the next frame; after
    // the last frame a fresh copy of the sphere starts the stroke again
    // (outside the timer). `perf_goals sculpt` reports its p50 / p99.
    let n2m = stroke::frequency_for(2_000_000);
    let s2m = settings(n2m);
    let base = HalfEdgeMesh::from_trimesh(&geodesic_sphere(1.0, n2m), "base").unwrap();
    let fresh = || {
        let mut sc = Sculptor::new(base.clone(), 0.25 * (s2m.brush_size() + s2m.influence));
        sc.begin_stroke();
        sc
    };
    let mut sc2 = fresh();
    let mut frame = 0usize;
    let size2 = s2m.brush_size();
    c.bench_function("sculpt_stroke_frame_2m", |b| {
        b.iter_custom(|iters| {
            let mut total = std::time::Duration::ZERO;
            for _ in 0..iters {
                if frame == FRAMES {
                    sc2 = fresh();
                    frame = 0;
                }
                let input = frame_input(&s2m, &smp, frame, size2);
                let t = Instant::now();
                black_box(sc2.apply_frame(&input));
                total += t.elapsed();
                frame += 1;
            }
            total
        })
    });
    c.final_summary();
}
