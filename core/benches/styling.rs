//! Styling per-frame costs with a reused factorization: curve smoother
//! frames (50 / 200 / 1000 control points: a frame at the same pointed
//! parameter reuses the numeric factors, so it is assembly + solve) and
//! surface smoother frames (32² / 64² / 128² control points: one solve with
//! three right-hand sides), plus the numeric refactorization a frame pays
//! when the weights change. SciPy SuperLU on the same systems:
//! `scripts/bench/styling.py`.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use shapewright::math::fm::DetMath as _;
use shapewright::nurbs::clamped_uniform_knots;
use shapewright::styling::solver::FixedSolver;
use shapewright::styling::surface::{SurfaceSystem, SurfaceWeights};
use shapewright::styling::tools::{CurveSession, SmoothParams};
use shapewright::styling::SplineCurve;

fn helix(n: usize) -> SplineCurve {
    let ctrl = (0..n)
        .map(|i| {
            let s = i as f64 / (n - 1) as f64;
            let a = 40.0 * s;
            [0.5 * s, 0.05 * a.fcos(), 0.05 * a.fsin()]
        })
        .collect();
    SplineCurve::new(clamped_uniform_knots(n, 3), ctrl).expect("helix")
}

fn curves(c: &mut Criterion) {
    let mut g = c.benchmark_group("curve_smoother_frame");
    g.sample_size(20);
    let p = SmoothParams {
        wb: 1e-7,
        ws: 0.0,
        wp0: 1.0,
        wp1: 0.0,
        wp2: 0.0,
        alpha: 8.0,
    };
    for n in [50usize, 200, 1000] {
        let curve = helix(n);
        let (a, b) = curve.domain();
        let t0 = 0.5 * (a + b);
        let mut s = CurveSession::new(curve.clone()).expect("session");
        s.smooth_step(&p, t0, 1.0).expect("frame");
        g.bench_with_input(BenchmarkId::new("reused_factor", n), &n, |bch, _| {
            bch.iter(|| s.smooth_step(&p, t0, 1.0).expect("frame"))
        });
        let mut k = 0usize;
        g.bench_with_input(BenchmarkId::new("refactor", n), &n, |bch, _| {
            bch.iter(|| {
                k += 1;
                let t = a + (b - a) * (0.4 + 0.2 * (k % 7) as f64 / 7.0);
                s.smooth_step(&p, t, 1.0).expect("frame")
            })
        });
    }
    g.finish();
}

fn surfaces(c: &mut Criterion) {
    let mut g = c.benchmark_group("surface_smoother_frame");
    g.sample_size(10);
    for n in [32usize, 64, 128] {
        let w = SurfaceWeights { wb: 1.0, ws: 0.01 };
        let mut sys = SurfaceSystem::new(n, n, &w, None).expect("system");
        let d0: Vec<[f64; 3]> = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                let (u, v) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
                [u, v, 0.05 * (9.0 * u).fsin() * (7.0 * v).fcos()]
            })
            .collect();
        let (a, fixed) = (sys.a.clone(), sys.fixed.clone());
        sys.solver.factor(&a, &fixed).expect("factor");
        let x0 = sys.columns(&d0);
        let rhs: Vec<f64> = sys
            .solver
            .pattern()
            .mul(&sys.a, &x0, 3)
            .iter()
            .map(|v| 0.9 * v)
            .collect();
        g.bench_with_input(BenchmarkId::new("reused_factor", n * n), &n, |bch, _| {
            bch.iter(|| sys.solver.solve(&rhs, &x0, 3).expect("solve"))
        });
        let pattern = sys.solver.pattern().clone();
        let mut fresh = FixedSolver::new(pattern).expect("symbolic");
        let mut scale = 1.0;
        g.bench_with_input(BenchmarkId::new("refactor", n * n), &n, |bch, _| {
            bch.iter(|| {
                scale += 1e-9;
                let a2: Vec<f64> = a.iter().map(|v| v * scale).collect();
                fresh.factor(&a2, &fixed).expect("factor")
            })
        });
    }
    g.finish();
}

criterion_group!(benches, curves, surfaces);
criterion_main!(benches);
