//! Benchmark of the SDF system, run by `scripts/bench/sdf.py` (which times
//! the NumPy + SciPy + scikit-image peer on the data this program dumps, in
//! the same run).
//!
//! `sdf_bench [--dump DIR] [--reps N] [--steps 0.01,0.006] [--no-full]`
//! prints one JSON object per line:
//! - `"kind":"table1"`: the paper's Table 1 workloads (Cube–Sphere, Chair,
//!   Cup; every operand a library component with its precomputed SDF, as
//!   in the paper) at each step: one `SdfVolume::updated` from an empty
//!   volume with every operand queued and no operand sampled yet (so the
//!   resampling of every operand is inside the timer, as in the peer), on
//!   all threads and on one; its parts (resample, fold, extraction); a
//!   drag frame (one operand moved, the others' samples reused); memory;
//!   triangles. Times are medians with the 25th–75th percentile spread.
//! - `"kind":"full"`: full-grid extraction of a sphere minus a torus at
//!   128³ and 256³: ours (all threads and one), fast-surface-nets, and the
//!   single-thread "classify every cell" floor, alternated rep by rep.
//!
//! With `--dump`, every operand's local grid, placement and the lattice box
//! are written (raw little-endian f32 plus JSON), so the peer resamples and
//! fuses the same data; the full grids too.

use shapewright::math::fm::DetMath as _;
use std::sync::Arc;
use std::time::Instant;

/// The hosts' allocator (see the workspace manifest).
#[global_allocator]
static ALLOC: mimalloc::MiMalloc = mimalloc::MiMalloc;

use fast_surface_nets::ndshape::RuntimeShape;
use fast_surface_nets::{surface_nets, SurfaceNetsBuffer};
use shapewright::sdf::csg::fuse_sampled;
use shapewright::sdf::features::ExactField;
use shapewright::sdf::grid::{Brick, SparseGrid, BRICK};
use shapewright::sdf::placement::{LocalField, PlacedField};
use shapewright::sdf::sample::sample_operand;
use shapewright::sdf::volume::stitch;
use shapewright::sdf::{Operand, SdfCache, SdfVolume};

/// The three Table 1 scenes, and the operand a drag moves in each.
fn workloads() -> Vec<(&'static str, Vec<Operand>, usize)> {
    shapewright::sdf::scenes::table1()
        .into_iter()
        .map(|s| (s.name, s.operands, s.dragged))
        .collect()
}

/// Median and the 25th / 75th percentiles.
fn stats(mut v: Vec<f64>) -> [f64; 3] {
    v.sort_by(|a, b| a.total_cmp(b));
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    [at(0.5), at(0.25), at(0.75)]
}

fn ms(s: Instant) -> f64 {
    s.elapsed().as_secs_f64() * 1e3
}

fn json3(x: [f64; 3]) -> String {
    format!("[{:.4},{:.4},{:.4}]", x[0], x[1], x[2])
}

fn write_f32(path: &str, v: &[f32]) {
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(path, bytes).expect("write grid");
}

/// Bytes a mesh holds (positions and normals f64, triangles u32).
fn mesh_bytes(m: &shapewright::mesh::TriMesh) -> usize {
    m.positions.len() * 24 + m.normals.len() * 24 + m.triangles.len() * 12
}

/// Counts the cells of a dense grid whose corners differ in sign.
fn classify(v: &[f32], dims: [usize; 3]) -> usize {
    let (nx, nxy) = (dims[0], dims[0] * dims[1]);
    let mut n = 0;
    for z in 0..dims[2] - 1 {
        for y in 0..dims[1] - 1 {
            let r = y * nx + z * nxy;
            let rows = [r, r + nx, r + nxy, r + nx + nxy];
            let mut pc = rows.iter().filter(|&&r| v[r] < 0.0).count();
            for x in 1..dims[0] {
                let cc = rows.iter().filter(|&&r| v[r + x] < 0.0).count();
                let s = pc + cc;
                n += (s != 0 && s != 8) as usize;
                pc = cc;
            }
        }
    }
    n
}

fn fsn_ms(v: &[f32], dims: [usize; 3], reps: usize) -> ([f64; 3], usize) {
    let shape = RuntimeShape::<u32, 3>::new(dims.map(|d| d as u32));
    let mut buf = SurfaceNetsBuffer::default();
    let mut times = Vec::new();
    for _ in 0..reps {
        let s = Instant::now();
        surface_nets(v, &shape, [0; 3], dims.map(|d| d as u32 - 1), &mut buf);
        times.push(ms(s));
    }
    (stats(times), buf.indices.len() / 3)
}

struct Args {
    dir: Option<String>,
    reps: usize,
    steps: Vec<f64>,
    full: bool,
    table1: bool,
    /// Profiling: loop one phase (`sample`, `fuse`, `extract`, `update`,
    /// `drag`) of one workload at the first step.
    phase: Option<(String, String)>,
}

fn args() -> Args {
    let a: Vec<String> = std::env::args().collect();
    let mut out = Args {
        dir: None,
        reps: 15,
        steps: vec![0.012, 0.01, 0.008, 0.006, 0.004],
        full: true,
        table1: true,
        phase: None,
    };
    let mut i = 1;
    while i < a.len() {
        match a[i].as_str() {
            "--dump" => {
                out.dir = a.get(i + 1).cloned();
                i += 1;
            }
            "--reps" => {
                out.reps = a.get(i + 1).and_then(|s| s.parse().ok()).unwrap_or(15);
                i += 1;
            }
            "--steps" => {
                if let Some(s) = a.get(i + 1) {
                    out.steps = s.split(',').filter_map(|x| x.parse().ok()).collect();
                }
                i += 1;
            }
            "--phase" => {
                if let (Some(w), Some(p)) = (a.get(i + 1), a.get(i + 2)) {
                    out.phase = Some((w.clone(), p.clone()));
                }
                i += 2;
            }
            "--no-full" => out.full = false,
            "--full-only" => out.table1 = false,
            _ => {}
        }
        i += 1;
    }
    out
}

fn table1(a: &Args, cache: &SdfCache, one: &rayon::ThreadPool) {
    let threads = rayon::current_num_threads();
    for (name, ops, drag) in workloads() {
        if let Some(d) = &a.dir {
            // Each operand's local grid and placement, once per scene.
            for (k, o) in ops.iter().enumerate() {
                let v = SdfVolume::new(0.01).expect("step");
                let f = v.placed_with(o, cache).expect("operand");
                let LocalField::Grid(g) = &f.field else {
                    panic!("bench operands are library components")
                };
                write_f32(&format!("{d}/{name}_op{k}.f32"), &g.sdf.values);
                let m = f.inverse.matrix3;
                let tr = f.inverse.translation;
                let (lo, hi) = f.world_box;
                std::fs::write(
                    format!("{d}/{name}_op{k}.json"),
                    format!(
                        "{{\"dims\":[{},{},{}],\"origin\":{},\"step\":{},\"inverse\":[{},{},{}],\"translation\":{},\"scale_min\":{},\"world_lo\":{},\"world_hi\":{},\"csg\":\"{}\"}}",
                        g.sdf.dims[0], g.sdf.dims[1], g.sdf.dims[2],
                        json3(g.sdf.origin),
                        g.sdf.step,
                        json3(m.row(0).to_array()), json3(m.row(1).to_array()), json3(m.row(2).to_array()),
                        json3(tr.to_array()),
                        f.scale_min,
                        json3(lo.to_array()),
                        json3(hi.to_array()),
                        format!("{:?}", o.csg).to_lowercase(),
                    ),
                )
                .expect("write operand");
            }
        }
        for &step in &a.steps {
            let band = (3.0 * step) as f32;
            let fresh = || {
                let mut v = SdfVolume::new(step).expect("step");
                v.pending = ops.clone();
                v
            };
            // One update, cold: a new volume (no operand sampled) each rep.
            let update = || {
                let v = fresh();
                let s = Instant::now();
                let u = v.updated_with(cache).expect("update");
                let t = ms(s);
                std::hint::black_box(u);
                t
            };
            let (mut t2, mut t1) = (Vec::new(), Vec::new());
            for _ in 0..a.reps {
                t2.push(update());
                t1.push(one.install(update));
            }
            // Its parts.
            let placed: Vec<_> = {
                let v = fresh();
                ops.iter()
                    .map(|o| Arc::new(v.placed_with(o, cache).expect("operand")))
                    .collect()
            };
            let exact = exact_field(&placed, &ops, band);
            let (mut ts, mut tf, mut te) = (Vec::new(), Vec::new(), Vec::new());
            let mut last = None;
            for _ in 0..a.reps {
                let s = Instant::now();
                let sampled: Vec<_> = placed
                    .iter()
                    .map(|p| sample_operand(p, step, band))
                    .collect();
                ts.push(ms(s));
                let s = Instant::now();
                let mut g = SparseGrid::new(step, band);
                for (so, o) in sampled.iter().zip(&ops) {
                    fuse_sampled(&mut g, so, o.csg);
                }
                tf.push(ms(s));
                let s = Instant::now();
                let pieces = g.extract_all(Some(&exact));
                let m = stitch(&pieces);
                te.push(ms(s));
                last = Some((g, sampled, pieces, m));
            }
            let (grid, sampled, pieces, mesh) = last.expect("reps > 0");
            // A drag frame: the moved operand resampled, the others' samples
            // reused, one update.
            let base = fresh();
            base.updated_with(cache).expect("warm");
            let mut td = Vec::new();
            for r in 0..a.reps {
                let v = base
                    .with_pending(|p| p[drag].transform.translate[0] += 0.0013 * (r + 1) as f64);
                let s = Instant::now();
                let u = v.updated_with(cache).expect("drag");
                td.push(ms(s));
                std::hint::black_box(u);
            }
            let piece_bytes: usize = pieces.values().map(|p| p.heap_bytes()).sum();
            let sample_bytes: usize = sampled.iter().map(|s| s.dense_bytes()).sum();
            // The lattice box of the result, one brick of margin, for the peer.
            let mut lo = [i32::MAX; 3];
            let mut hi = [i32::MIN; 3];
            for k in grid.bricks.keys() {
                for ax in 0..3 {
                    lo[ax] = lo[ax].min((k[ax] - 1) * BRICK);
                    hi[ax] = hi[ax].max((k[ax] + 2) * BRICK - 1);
                }
            }
            let dense_bricks = grid
                .bricks
                .values()
                .filter(|b| matches!(b, Brick::Dense(_)))
                .count();
            println!(
                "{{\"kind\":\"table1\",\"workload\":\"{name}\",\"step\":{step},\"threads\":{threads},\"operands\":{},\"update_ms\":{},\"update_1t_ms\":{},\"sample_ms\":{},\"fuse_ms\":{},\"extract_ms\":{},\"drag_ms\":{},\"triangles\":{},\"dense_bricks\":{dense_bricks},\"grid_bytes\":{},\"sample_bytes\":{sample_bytes},\"piece_bytes\":{piece_bytes},\"mesh_bytes\":{},\"lattice_lo\":[{},{},{}],\"lattice_hi\":[{},{},{}],\"band\":{band}}}",
                ops.len(),
                json3(stats(t2)),
                json3(stats(t1)),
                json3(stats(ts)),
                json3(stats(tf)),
                json3(stats(te)),
                json3(stats(td)),
                mesh.triangle_count(),
                grid.dense_bytes(),
                mesh_bytes(&mesh),
                lo[0], lo[1], lo[2], hi[0], hi[1], hi[2],
            );
        }
    }
}

/// The dense `n`³ sphere-minus-torus field of the full-grid rows, and the
/// same in bricks (clamped to the band), as the volume stores it.
fn full_grid(n: usize) -> (Vec<f32>, SparseGrid) {
    let h = 1.0 / n as f64;
    let c = n as f64 * h * 0.5;
    let mut dense = vec![0f32; n * n * n];
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let p = [x as f64 * h - c, y as f64 * h - c, z as f64 * h - c];
                let sphere = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 0.4;
                let torus = ((p[0] * p[0] + p[1] * p[1]).sqrt() - 0.3).fhypot(p[2]) - 0.12;
                dense[x + n * (y + n * z)] = sphere.max(-torus) as f32;
            }
        }
    }
    // Into bricks (clamped to the band), then extraction as the volume
    // does it.
    let band = (3.0 * h) as f32;
    let mut g = SparseGrid::new(h, band);
    let nb = (n as i32) / BRICK;
    for bz in 0..nb {
        for by in 0..nb {
            for bx in 0..nb {
                let mut d = vec![0f32; 512];
                for (l, dl) in d.iter_mut().enumerate() {
                    let (x, y, z) = (l % 8, l / 8 % 8, l / 64);
                    let gx = bx as usize * 8 + x;
                    let gy = by as usize * 8 + y;
                    let gz = bz as usize * 8 + z;
                    *dl = dense[gx + n * (gy + n * gz)].clamp(-band, band);
                }
                g.set([bx, by, bz], Brick::dense(d, band));
            }
        }
    }
    (dense, g)
}

fn full(a: &Args, one: &rayon::ThreadPool) {
    let threads = rayon::current_num_threads();
    for n in [128usize, 256] {
        let dims = [n; 3];
        let (dense, g) = full_grid(n);
        // Ours and the classify floor alternate, rep by rep, so that a
        // noisy machine slows both alike.
        let extract = || {
            let s = Instant::now();
            let pieces = g.extract_all(None);
            let m = stitch(&pieces);
            let t = ms(s);
            drop(pieces);
            (t, m.triangle_count())
        };
        let (mut t2, mut t1, mut ct) = (Vec::new(), Vec::new(), Vec::new());
        let (mut tris, mut cells) = (0, 0);
        for _ in 0..a.reps.max(21) {
            let (t, tr) = extract();
            t2.push(t);
            tris = tr;
            t1.push(one.install(extract).0);
            let s = Instant::now();
            cells = std::hint::black_box(classify(&dense, dims));
            ct.push(ms(s));
        }
        let (fsn, fsn_tris) = fsn_ms(&dense, dims, a.reps.clamp(5, 11));
        if let Some(d) = &a.dir {
            write_f32(&format!("{d}/full_{n}.f32"), &dense);
        }
        println!(
            "{{\"kind\":\"full\",\"n\":{n},\"threads\":{threads},\"ours_ms\":{},\"ours_1t_ms\":{},\"triangles\":{tris},\"classify_ms\":{},\"crossing_cells\":{cells},\"fsn_ms\":{},\"fsn_triangles\":{fsn_tris},\"tag\":\"full_{n}\"}}",
            json3(stats(t2)),
            json3(stats(t1)),
            json3(stats(ct)),
            json3(fsn),
        );
    }
}

/// Loops one phase for a profiler (`perf stat -e task-clock` gives its
/// CPU time, which a loaded machine inflates far less than wall time).
fn phase(a: &Args, cache: &SdfCache, workload: &str, phase: &str) {
    if workload == "hash" {
        // `--phase hash all`: a hash of every extraction's mesh (positions,
        // normals, triangles), to check that a change keeps the bits.
        let h = |m: &shapewright::mesh::TriMesh| {
            use std::hash::{Hash, Hasher};
            let mut s = std::collections::hash_map::DefaultHasher::new();
            for p in m.positions.iter().chain(&m.normals) {
                p.map(f64::to_bits).hash(&mut s);
            }
            m.triangles.hash(&mut s);
            s.finish()
        };
        for n in [64usize, 128, 256] {
            let (_, g) = full_grid(n);
            let m = stitch(&g.extract_all(None));
            println!("full {n}: {} tris {:016x}", m.triangle_count(), h(&m));
        }
        for (name, ops, drag) in workloads() {
            for step in [0.012, 0.01, 0.006, 0.004] {
                let mut v = SdfVolume::new(step).expect("step");
                v.pending = ops.clone();
                let u = v.updated_with(cache).expect("update");
                let m = u.state_with(cache).expect("state").mesh.clone();
                println!("{name} {step}: {} tris {:016x}", m.triangle_count(), h(&m));
                // A drag: incremental re-extraction of the moved bricks.
                let d = v
                    .with_pending(|p| p[drag].transform.translate[0] += 0.0137)
                    .updated_with(cache)
                    .expect("drag");
                let m = d.state_with(cache).expect("state").mesh.clone();
                println!(
                    "{name} {step} drag: {} tris {:016x}",
                    m.triangle_count(),
                    h(&m)
                );
            }
        }
        return;
    }
    if workload == "full" {
        // `--phase full N`: the full-grid extraction at N³ (ours only).
        let n: usize = phase.parse().expect("--phase full N");
        let (_, g) = full_grid(n);
        let (mut times, mut te, mut ta) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..a.reps {
            let s = Instant::now();
            let pieces = g.extract_all(None);
            te.push(ms(s));
            let s2 = Instant::now();
            std::hint::black_box(stitch(&pieces));
            ta.push(ms(s2));
            drop(pieces);
            times.push(ms(s));
        }
        eprintln!(
            "pieces {:.3} ms, assemble {:.3} ms (medians)",
            stats(te)[0],
            stats(ta)[0]
        );
        let min = times.iter().copied().fold(f64::INFINITY, f64::min);
        let [med, p25, p75] = stats(times);
        eprintln!("full {n}: min {min:.3} ms, median {med:.3} ({p25:.3}..{p75:.3}) per rep (wall)");
        return;
    }
    let (_, ops, drag) = workloads()
        .into_iter()
        .find(|w| w.0 == workload)
        .expect("workload");
    let step = a.steps[0];
    let band = (3.0 * step) as f32;
    let v = SdfVolume::new(step).expect("step");
    let placed: Vec<_> = ops
        .iter()
        .map(|o| Arc::new(v.placed_with(o, cache).expect("operand")))
        .collect();
    let exact = exact_field(&placed, &ops, band);
    let sampled: Vec<_> = placed
        .iter()
        .map(|p| sample_operand(p, step, band))
        .collect();
    for (k, so) in sampled.iter().enumerate() {
        eprintln!(
            "operand {k}: {} region bricks, {} evaluated, {} stored",
            so.region_bricks,
            so.evaluated_bricks,
            so.bricks.len()
        );
    }
    let mut g = SparseGrid::new(step, band);
    for (so, o) in sampled.iter().zip(&ops) {
        fuse_sampled(&mut g, so, o.csg);
    }
    let mut base = SdfVolume::new(step).expect("step");
    base.pending = ops.clone();
    base.updated_with(cache).expect("warm");
    let mut times = Vec::new();
    for r in 0..a.reps {
        let s = Instant::now();
        match phase {
            "sample" => {
                std::hint::black_box(
                    placed
                        .iter()
                        .map(|p| sample_operand(p, step, band))
                        .collect::<Vec<_>>(),
                );
            }
            "fuse" => {
                let mut g = SparseGrid::new(step, band);
                for (so, o) in sampled.iter().zip(&ops) {
                    fuse_sampled(&mut g, so, o.csg);
                }
                std::hint::black_box(g);
            }
            "extract" => {
                std::hint::black_box(stitch(&g.extract_all(Some(&exact))));
            }
            "extract_plain" => {
                std::hint::black_box(stitch(&g.extract_all(None)));
            }
            "update" => {
                let mut v = SdfVolume::new(step).expect("step");
                v.pending = ops.clone();
                std::hint::black_box(v.updated_with(cache).expect("update"));
            }
            "drag" => {
                let v = base
                    .with_pending(|p| p[drag].transform.translate[0] += 0.0013 * (r + 1) as f64);
                std::hint::black_box(v.updated_with(cache).expect("drag"));
            }
            _ => panic!("unknown phase {phase}"),
        }
        times.push(ms(s));
    }
    let min = times.iter().copied().fold(f64::INFINITY, f64::min);
    let [med, p25, p75] = stats(times);
    eprintln!("{phase}: min {min:.3} ms, median {med:.3} ({p25:.3}..{p75:.3}) per rep (wall)");
}

fn main() {
    let a = args();
    if let Some((w, p)) = &a.phase {
        let cache = SdfCache::new();
        phase(&a, &cache, w, p);
        return;
    }
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    // The components' SDFs are precomputed (§5.2), as the peer's are.
    let cache = SdfCache::new();
    if a.table1 {
        for (_, ops, _) in workloads() {
            let v = SdfVolume::new(0.01).expect("step");
            for o in &ops {
                v.placed_with(o, &cache).expect("operand");
            }
        }
        table1(&a, &cache, &one);
    }
    if a.full {
        full(&a, &one);
    }
}

/// The exact CSG field of placed operands with their operations, within
/// `band` of the surface.
fn exact_field(placed: &[Arc<PlacedField>], ops: &[Operand], band: f32) -> ExactField {
    ExactField::new(
        placed
            .iter()
            .cloned()
            .zip(ops.iter().map(|o| o.csg))
            .collect(),
        band as f64,
    )
}
