//! The goal measurements of issue 21 that have no peer, for the honest
//! bench (`scripts/bench/run_all.py`); each prints one JSON line.
//!
//! - `perf_goals sculpt VERTS REPS`: the bench stroke
//!   (`benches/fixtures/sculpt_stroke.rs`, the same as `cargo bench
//!   --bench sculpt`: a 200-frame warp drag, brush radius 0.1 + influence
//!   0.1) on a geodesic sphere of about VERTS vertices, REPS times, each on
//!   a fresh copy of the mesh. Timed: each frame's `Sculptor::apply_frame`
//!   (wall clock), nothing else (the mesh and the sculptor's index are
//!   built before the stroke, as when the user starts a stroke on an
//!   existing object; the index build is reported as `index_ms`). Reports
//!   per rep the p50 / p99 / max frame, and the median and 25th–75th
//!   percentiles of the per-rep p99 (the goal's number), plus the mean
//!   on-CPU time per frame (schedstat) so preemption on a busy machine
//!   Every rep must give the same mesh (checked).
//! - `perf_goals gc-commit REPS`: the commit of every GC op in the teapot
//!   trace (`tests/data/teapot.trace.jsonl`, replayed through the session
//!   to get its ops), the chair script (`tests/data/chair.jsonl`) and the
//!   30-part shelf (`tests/data/bench/shelf.jsonl`: legs, posts, rails,
//!   stretchers and slats, then four edits; in a folder of its own so the
//!   slicer, USD and Windows tests, which take every script in
//!   `tests/data`, do not spend CI time on it): each
//!   op's `OpLog::apply` (the op, the assembly's re-evaluation: meshing
//!   every part, cavities, the manifold union, validation, and the log's
//!   checkpointing), REPS times from an empty log. Reports p50 / p99 / max
//!   over all (op, rep) samples, the slowest op kind, and the median and
//!   25th–75th percentiles of the per-rep p99.
//!
//! Threads: rayon's default (all cores). Allocator: mimalloc, the hosts'.

use std::time::Instant;

#[global_allocator]
static ALLOC: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[path = "../benches/fixtures/sculpt_stroke.rs"]
mod stroke;

use shapewright::doc::{parse_script, run_script, Op, OpLog};
use shapewright::interact::trace::{replay, Trace};
use shapewright::sculpt::base::geodesic_sphere;
use shapewright::sculpt::HalfEdgeMesh;
use stroke::{frequency_for, pct, run_frames, settings, FRAMES};

type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// Median, 25th and 75th percentiles (nearest rank).
fn quartiles(v: &[f64]) -> [f64; 3] {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    [pct(&s, 0.5), pct(&s, 0.25), pct(&s, 0.75)]
}

fn json_list(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| format!("{x:.4}")).collect();
    format!("[{}]", items.join(","))
}

fn sculpt(verts: usize, reps: usize) -> Res<()> {
    let n = frequency_for(verts);
    let base = HalfEdgeMesh::from_trimesh(&geodesic_sphere(1.0, n), "base")?;
    let s = settings(n);
    let (mut p50, mut p99, mut max, mut index) = (vec![], vec![], vec![], vec![]);
    let mut first = None;
    let mut moved = 0;
    for _ in 0..reps.max(1) {
        let r = run_frames(base.clone(), &s);
        let mut t = r.times.clone();
        t.sort_by(f64::total_cmp);
        p50.push(pct(&t, 0.5));
        p99.push(pct(&t, 0.99));
        max.push(t[t.len() - 1]);
        index.push(r.index_ms);
        moved = r.per_frame.iter().map(|f| f.0).max().unwrap_or(0);
        match &first {
            None => first = Some(r.sculptor.mesh().clone()),
            Some(m) => {
                if m != r.sculptor.mesh() {
                    return Err("reps of the stroke gave different meshes".into());
                }
            }
        }
    }
    println!(
        "{{\"kind\":\"sculpt\",\"vertices\":{},\"frequency\":{n},\"frames\":{FRAMES},\"reps\":{},\"threads\":{},\"p99_ms\":{},\"p50_ms\":{},\"max_ms\":{},\"p99_per_rep\":{},\"index_ms\":{},\"max_moved_per_frame\":{moved}}}",
        base.vertex_count(),
        reps.max(1),
        rayon::current_num_threads(),
        json_list(&quartiles(&p99)),
        json_list(&quartiles(&p50)),
        json_list(&quartiles(&max)),
        json_list(&p99),
        json_list(&quartiles(&index)),
    );
    Ok(())
}

/// The ops of the teapot trace's session and of the chair script.
fn gc_sessions() -> Res<Vec<(&'static str, Vec<Op>)>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/");
    let trace = Trace::from_jsonl(&std::fs::read_to_string(format!(
        "{root}teapot.trace.jsonl"
    ))?)?;
    let r = replay(&trace)?;
    let teapot = r.log.ops()[..r.log.cursor()].to_vec();
    let mut log = OpLog::new();
    run_script(
        &mut log,
        &parse_script(&std::fs::read_to_string(format!("{root}chair.jsonl"))?)?,
    )?;
    let chair = log.ops()[..log.cursor()].to_vec();
    let mut log = OpLog::new();
    run_script(
        &mut log,
        &parse_script(&std::fs::read_to_string(format!(
            "{root}bench/shelf.jsonl"
        ))?)?,
    )?;
    let shelf = log.ops()[..log.cursor()].to_vec();
    Ok(vec![("teapot", teapot), ("chair", chair), ("shelf", shelf)])
}

fn gc_commit(reps: usize) -> Res<()> {
    for (name, ops) in gc_sessions()? {
        let gc_ops: Vec<&str> = ops.iter().map(|o| o.name()).collect();
        if !gc_ops.iter().all(|k| k.starts_with("gc_")) {
            return Err(format!("{name}: not only GC ops: {gc_ops:?}").into());
        }
        let mut all = Vec::new();
        let mut p99 = Vec::new();
        let mut slowest = (0.0, "");
        for _ in 0..reps.max(1) {
            let mut log = OpLog::new();
            let mut rep = Vec::with_capacity(ops.len());
            for op in &ops {
                let kind = op.name();
                let op = op.clone();
                let t = Instant::now();
                log.apply(op)?;
                let ms = t.elapsed().as_secs_f64() * 1e3;
                if ms > slowest.0 {
                    slowest = (ms, kind);
                }
                rep.push(ms);
            }
            rep.sort_by(f64::total_cmp);
            p99.push(pct(&rep, 0.99));
            all.extend(rep);
        }
        all.sort_by(f64::total_cmp);
        let mut kinds: Vec<&str> = gc_ops.clone();
        kinds.sort_unstable();
        kinds.dedup();
        println!(
            "{{\"kind\":\"gc_commit\",\"session\":\"{name}\",\"ops\":{},\"op_kinds\":{:?},\"reps\":{},\"threads\":{},\"p99_ms\":{},\"p50_all_ms\":{:.4},\"p99_all_ms\":{:.4},\"max_ms\":{:.4},\"slowest_op\":\"{}\"}}",
            ops.len(),
            kinds,
            reps.max(1),
            rayon::current_num_threads(),
            json_list(&quartiles(&p99)),
            pct(&all, 0.5),
            pct(&all, 0.99),
            all[all.len() - 1],
            slowest.1,
        );
    }
    Ok(())
}

fn main() -> Res<()> {
    let a: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: usize| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    match a.get(1).map(String::as_str) {
        Some("sculpt") => sculpt(num(2, 2_000_000), num(3, 3)),
        Some("gc-commit") => gc_commit(num(2, 5)),
        _ => Err("usage: perf_goals sculpt VERTS REPS | gc-commit REPS".into()),
    }
}
