//! Benchmark of the SDF system, run by scripts/bench/sdf.py (which adds the
//! NumPy + scikit-image peer on the grids this program dumps).
//!
//! `sdf_bench [--dump DIR] [--reps N]` prints one JSON object per line:
//! - the paper's Table 1 workloads (Cube–Sphere, Chair, Cup) at steps
//!   0.012 / 0.01 / 0.008 / 0.006: fusion ms, extraction ms, total update
//!   ms (one `SdfVolume::updated` from an empty volume), triangles, and
//!   fast-surface-nets on the same fused grid made dense;
//! - full-grid extraction of a sphere minus a torus at 128³ and 256³: ours
//!   (on 1 and on all threads), fast-surface-nets and a "classify the
//!   cells" floor (sign mask of every cell, single thread).
//!
//! With `--dump`, each grid is written as raw little-endian f32 (x
//! fastest) plus a JSON sidecar, and each Table 1 workload also dumps
//! every operand's field on the same box, so the peer fuses the same data.

use std::time::Instant;

/// The hosts' allocator (see the workspace manifest).
#[global_allocator]
static ALLOC: mimalloc::MiMalloc = mimalloc::MiMalloc;

use fast_surface_nets::ndshape::RuntimeShape;
use fast_surface_nets::{surface_nets, SurfaceNetsBuffer};
use shapewright::math::Transform;
use shapewright::sdf::csg::fuse;
use shapewright::sdf::features::ExactField;
use shapewright::sdf::grid::{Brick, SparseGrid, BRICK};
use shapewright::sdf::volume::stitch;
use shapewright::sdf::{Component, CsgOp, Operand, SdfVolume};
use shapewright::solid::SolidShape;

fn solid(shape: SolidShape) -> Component {
    Component::Solid { shape }
}

fn lib(name: &str) -> Component {
    Component::Library { name: name.into() }
}

fn t(tr: [f64; 3], q: [f64; 4], s: [f64; 3]) -> Transform {
    Transform {
        translate: tr,
        rotate: q,
        scale: s,
    }
}

const ID: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

fn workloads() -> Vec<(&'static str, Vec<Operand>)> {
    let o = |component, csg, transform| Operand {
        component,
        csg,
        transform,
    };
    let s2 = 0.5f64.sqrt();
    let leg = |x: f64, y: f64| {
        o(
            lib("chair_leg"),
            CsgOp::Union,
            t([x, y, 0.22], ID, [1.0, 1.0, 1.1]),
        )
    };
    vec![
        (
            "cube_sphere",
            vec![
                o(lib("box"), CsgOp::Union, t([0.0; 3], ID, [1.0; 3])),
                o(
                    lib("sphere"),
                    CsgOp::Union,
                    t([0.15, 0.1, 0.1], ID, [1.2; 3]),
                ),
            ],
        ),
        (
            "chair",
            vec![
                o(
                    lib("chair_seat"),
                    CsgOp::Union,
                    t([0.0, 0.0, 0.455], ID, [1.0; 3]),
                ),
                leg(0.17, 0.17),
                leg(-0.17, 0.17),
                leg(0.17, -0.17),
                leg(-0.17, -0.17),
                o(
                    lib("chair_back"),
                    CsgOp::Union,
                    t([0.0, 0.178, 0.69], ID, [1.1; 3]),
                ),
            ],
        ),
        (
            "cup",
            vec![
                o(
                    solid(SolidShape::Cylinder {
                        radius: 0.12,
                        height: 0.24,
                    }),
                    CsgOp::Union,
                    t([0.0; 3], ID, [1.0; 3]),
                ),
                o(
                    solid(SolidShape::Torus {
                        major_radius: 0.06,
                        minor_radius: 0.015,
                    }),
                    CsgOp::Union,
                    t([0.17, 0.0, 0.0], [s2, 0.0, 0.0, s2], [1.0; 3]),
                ),
                o(
                    solid(SolidShape::Cylinder {
                        radius: 0.105,
                        height: 0.24,
                    }),
                    CsgOp::Subtract,
                    t([0.0, 0.0, 0.03], ID, [1.0; 3]),
                ),
            ],
        ),
    ]
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// The grid as a dense array over the bounding box of its stored bricks
/// (one brick of margin), `+band` where nothing is stored.
fn densify(g: &SparseGrid, lo: [i32; 3], hi: [i32; 3]) -> (Vec<f32>, [usize; 3]) {
    let dims = [0, 1, 2].map(|a| ((hi[a] - lo[a] + 1) * BRICK) as usize);
    let mut out = vec![g.band; dims[0] * dims[1] * dims[2]];
    for (k, b) in &g.bricks {
        if (0..3).any(|a| k[a] < lo[a] || k[a] > hi[a]) {
            continue;
        }
        for l in 0..512usize {
            let (x, y, z) = (l % 8, l / 8 % 8, l / 64);
            let gx = ((k[0] - lo[0]) * BRICK) as usize + x;
            let gy = ((k[1] - lo[1]) * BRICK) as usize + y;
            let gz = ((k[2] - lo[2]) * BRICK) as usize + z;
            out[gx + dims[0] * (gy + dims[1] * gz)] = match b {
                Brick::Uniform(v) => *v,
                Brick::Dense(d) => d[l],
            };
        }
    }
    (out, dims)
}

fn brick_box(g: &SparseGrid) -> ([i32; 3], [i32; 3]) {
    let mut lo = [i32::MAX; 3];
    let mut hi = [i32::MIN; 3];
    for k in g.bricks.keys() {
        for a in 0..3 {
            lo[a] = lo[a].min(k[a] - 1);
            hi[a] = hi[a].max(k[a] + 1);
        }
    }
    (lo, hi)
}

fn dump(dir: &Option<String>, name: &str, v: &[f32], dims: [usize; 3], step: f64) {
    if let Some(d) = dir {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        std::fs::write(format!("{d}/{name}.f32"), bytes).expect("write grid");
        std::fs::write(
            format!("{d}/{name}.json"),
            format!(
                "{{\"dims\":[{},{},{}],\"step\":{step}}}",
                dims[0], dims[1], dims[2]
            ),
        )
        .expect("write sidecar");
    }
}

fn fsn_ms(v: &[f32], dims: [usize; 3], reps: usize) -> (f64, usize) {
    let shape = RuntimeShape::<u32, 3>::new(dims.map(|d| d as u32));
    let mut buf = SurfaceNetsBuffer::default();
    let mut times = Vec::new();
    for _ in 0..reps {
        let s = Instant::now();
        surface_nets(v, &shape, [0; 3], dims.map(|d| d as u32 - 1), &mut buf);
        times.push(s.elapsed().as_secs_f64() * 1e3);
    }
    (median(times), buf.indices.len() / 3)
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

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut dir = None;
    let mut reps = 15usize;
    let mut full_only = false;
    let mut i = 1;
    while i < args.len() {
        match args[i].as_str() {
            "--dump" => {
                dir = args.get(i + 1).cloned();
                i += 1;
            }
            "--full-only" => full_only = true,
            "--reps" => {
                reps = args.get(i + 1).and_then(|s| s.parse().ok()).unwrap_or(reps);
                i += 1;
            }
            _ => {}
        }
        i += 1;
    }
    let threads = rayon::current_num_threads();
    let workloads = if full_only { Vec::new() } else { workloads() };
    for (name, ops) in workloads {
        for step in [0.012, 0.01, 0.008, 0.006] {
            let mut v = SdfVolume::new(step).expect("step");
            let placed: Vec<_> = ops
                .iter()
                .map(|o| std::sync::Arc::new(v.placed(o).expect("operand")))
                .collect();
            // Sharp features with exact normals, as the volume extracts.
            let exact = ExactField::new(
                placed
                    .iter()
                    .cloned()
                    .zip(ops.iter().map(|o| o.csg))
                    .collect(),
                3.0 * step,
            );
            let (mut tf, mut te, mut tt) = (Vec::new(), Vec::new(), Vec::new());
            let mut tris = 0;
            let mut grid = SparseGrid::new(step, (3.0 * step) as f32);
            for _ in 0..reps {
                let s = Instant::now();
                let mut g = SparseGrid::new(step, (3.0 * step) as f32);
                for (p, o) in placed.iter().zip(&ops) {
                    fuse(&mut g, p, o.csg);
                }
                let f = s.elapsed().as_secs_f64() * 1e3;
                let s = Instant::now();
                // Pieces are kept past the timing, as the volume keeps them.
                let pieces = g.extract_all(Some(&exact));
                let m = stitch(&pieces);
                te.push(s.elapsed().as_secs_f64() * 1e3);
                drop(pieces);
                tf.push(f);
                tris = m.triangle_count();
                grid = g;
            }
            v.pending = ops.clone();
            for _ in 0..reps {
                let s = Instant::now();
                let u = v.updated().expect("update");
                tt.push(s.elapsed().as_secs_f64() * 1e3);
                std::hint::black_box(u);
            }
            let (lo, hi) = brick_box(&grid);
            let (dense, dims) = densify(&grid, lo, hi);
            let (fsn, fsn_tris) = fsn_ms(&dense, dims, reps.min(5));
            let tag = format!("{name}_{}", (step * 1000.0).round() as i32);
            dump(&dir, &tag, &dense, dims, step);
            for (k, (p, o)) in placed.iter().zip(&ops).enumerate() {
                let mut g = SparseGrid::new(step, (3.0 * step) as f32);
                fuse(&mut g, p, CsgOp::Union);
                let (d, _) = densify(&g, lo, hi);
                dump(
                    &dir,
                    &format!("{tag}_op{k}_{:?}", o.csg).to_lowercase(),
                    &d,
                    dims,
                    step,
                );
            }
            println!(
                "{{\"kind\":\"table1\",\"workload\":\"{name}\",\"step\":{step},\"threads\":{threads},\"fusion_ms\":{:.3},\"extraction_ms\":{:.3},\"update_ms\":{:.3},\"triangles\":{tris},\"dense_dims\":[{},{},{}],\"fsn_ms\":{fsn:.3},\"fsn_triangles\":{fsn_tris},\"tag\":\"{tag}\",\"operands\":{}}}",
                median(tf),
                median(te),
                median(tt),
                dims[0],
                dims[1],
                dims[2],
                ops.len()
            );
        }
    }
    for n in [128usize, 256] {
        let h = 1.0 / n as f64;
        let c = n as f64 * h * 0.5;
        let dims = [n; 3];
        let mut dense = vec![0f32; n * n * n];
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let p = [x as f64 * h - c, y as f64 * h - c, z as f64 * h - c];
                    let sphere = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 0.4;
                    let torus = ((p[0] * p[0] + p[1] * p[1]).sqrt() - 0.3).hypot(p[2]) - 0.12;
                    dense[x + n * (y + n * z)] = sphere.max(-torus) as f32;
                }
            }
        }
        // Into bricks (clamped to the band), then extraction as the
        // volume does it.
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
        // Ours and the classify floor alternate, rep by rep, so that a
        // noisy machine slows both alike; medians of each.
        let extract = || {
            let s = Instant::now();
            let pieces = g.extract_all(None);
            let m = stitch(&pieces);
            let ms = s.elapsed().as_secs_f64() * 1e3;
            drop(pieces);
            (ms, m.triangle_count())
        };
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool");
        let (mut t2, mut t1, mut ct) = (Vec::new(), Vec::new(), Vec::new());
        let (mut tris, mut cells) = (0, 0);
        for _ in 0..reps.max(41) {
            let (ms, t) = extract();
            t2.push(ms);
            tris = t;
            let s = Instant::now();
            cells = std::hint::black_box(classify(&dense, dims));
            ct.push(s.elapsed().as_secs_f64() * 1e3);
        }
        for _ in 0..reps.max(15) {
            t1.push(one.install(extract).0);
        }
        let (ours, ours1) = (median(t2), median(t1));
        let (fsn, fsn_tris) = fsn_ms(&dense, dims, reps.min(5));
        dump(&dir, &format!("full_{n}"), &dense, dims, h);
        println!(
            "{{\"kind\":\"full\",\"n\":{n},\"threads\":{threads},\"ours_ms\":{ours:.3},\"ours_1thread_ms\":{ours1:.3},\"triangles\":{tris},\"classify_ms\":{:.3},\"crossing_cells\":{cells},\"fsn_ms\":{fsn:.3},\"fsn_triangles\":{fsn_tris},\"tag\":\"full_{n}\"}}",
            median(ct)
        );
    }
}
