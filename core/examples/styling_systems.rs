//! Builds the styling benchmark systems (curve smoother frames with 50, 200
//! and 1000 control points; surface smoother frames with 32², 64² and 128²
//! control points), times Shapewright's factorization and per-frame solve
//! on them, and writes each eliminated system as Matrix Market files
//! (`<name>.mtx`, `<name>_rhs.mtx`) for `scripts/bench/styling.py`, which
//! times SciPy's SuperLU on the same systems in the same run.
//!
//! Usage: `cargo run --release --example styling_systems -- OUT_DIR`.
//! Prints one JSON object per system on stdout.
#![allow(missing_docs, clippy::needless_range_loop)]

use shapewright::math::fm::DetMath as _;
use std::io::Write;
use std::time::Instant;

use shapewright::nurbs::clamped_uniform_knots;
use shapewright::styling::energy::{curve_pattern, flatten, CurveSystem, Weight};
use shapewright::styling::solver::{FixedSolver, SymPattern};
use shapewright::styling::surface::{SurfaceSystem, SurfaceWeights};
use shapewright::styling::tools::fixed_outside;
use shapewright::styling::SplineCurve;

fn helix(n: usize) -> SplineCurve {
    let ctrl = (0..n)
        .map(|i| {
            let s = i as f64 / (n - 1) as f64;
            let a = 40.0 * s + 0.3 * ((i * 7919 % 13) as f64 / 13.0);
            [0.5 * s, 0.05 * a.fcos(), 0.05 * a.fsin()]
        })
        .collect();
    SplineCurve::new(clamped_uniform_knots(n, 3), ctrl).expect("helix")
}

fn bumpy(n: usize) -> Vec<[f64; 3]> {
    let mut d = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
            let z = 0.05 * (9.0 * u).fsin() * (7.0 * v).fcos()
                + 0.005 * (((i * 31 + j * 17) % 7) as f64 - 3.0);
            d.push([u, v, z]);
        }
    }
    d
}

/// Quartiles `[p25, p50, p75]` of a sample of times.
fn quartiles(mut v: Vec<f64>) -> [f64; 3] {
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    [at(0.25), at(0.5), at(0.75)]
}

fn time<T>(reps: usize, mut f: impl FnMut() -> T) -> [f64; 3] {
    quartiles(
        (0..reps)
            .map(|_| {
                let t = Instant::now();
                std::hint::black_box(f());
                t.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

fn write_mtx(path: &std::path::Path, p: &SymPattern, values: &[f64]) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(f, "%%MatrixMarket matrix coordinate real symmetric")?;
    writeln!(f, "{} {} {}", p.n(), p.n(), p.nnz())?;
    for c in 0..p.n() {
        for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
            writeln!(f, "{} {} {:e}", p.row_idx()[k] + 1, c + 1, values[k])?;
        }
    }
    Ok(())
}

fn write_dense(path: &std::path::Path, n: usize, k: usize, x: &[f64]) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(f, "%%MatrixMarket matrix array real general")?;
    writeln!(f, "{n} {k}")?;
    for v in x {
        writeln!(f, "{v:e}")?;
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn report(
    out: &std::path::Path,
    name: &str,
    solver: &FixedSolver,
    k: usize,
    x: &[f64],
    symbolic_s: f64,
    factor_s: [f64; 3],
    solve_s: [f64; 3],
) -> std::io::Result<()> {
    let p = solver.pattern();
    write_mtx(&out.join(format!("{name}.mtx")), p, solver.reduced())?;
    let b = p.mul(solver.reduced(), x, k);
    write_dense(&out.join(format!("{name}_rhs.mtx")), p.n(), k, &b)?;
    write_dense(&out.join(format!("{name}_x.mtx")), p.n(), k, x)?;
    let ms = |q: [f64; 3]| format!("[{:.5},{:.5},{:.5}]", q[0] * 1e3, q[1] * 1e3, q[2] * 1e3);
    println!(
        "{{\"name\":\"{name}\",\"n\":{},\"nnz_lower\":{},\"rhs\":{k},\"symbolic_ms\":{:.4},\"factor_ms\":{},\"solve_ms\":{},\"factor\":\"{}\"}}",
        p.n(),
        p.nnz(),
        symbolic_s * 1e3,
        ms(factor_s),
        ms(solve_s),
        solver.describe()
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/styling_systems".into()),
    );
    std::fs::create_dir_all(&out)?;
    for n in [50usize, 200, 1000] {
        let c = helix(n);
        let reps = if n > 500 { 15 } else { 40 };
        let symbolic_s = time(reps, || FixedSolver::new(curve_pattern(n)).map(|_| ()))[1];
        let mut sys = CurveSystem::new(&c, curve_pattern(n));
        let w = Weight::gaussian(0.5, 8.0);
        sys.add_bend(1e-7, w);
        sys.add_shape(0, 1.0, &c);
        let (ta, tb) = w.support();
        let fixed = fixed_outside(&c, ta, tb);
        let mut solver = FixedSolver::new(curve_pattern(n))?;
        let mut v = Vec::new();
        for _ in 0..reps {
            let mut s = FixedSolver::new(curve_pattern(n))?;
            let t = Instant::now();
            s.factor(&sys.values, &fixed)?;
            v.push(t.elapsed().as_secs_f64());
        }
        let factor_s = quartiles(v);
        solver.factor(&sys.values, &fixed)?;
        let e = flatten(&c.ctrl);
        let x = solver.solve(&sys.rhs, &e, 1)?;
        let solve_s = time(reps * 5, || solver.solve(&sys.rhs, &e, 1).expect("solve"));
        report(
            &out,
            &format!("curve_{n}"),
            &solver,
            1,
            &x,
            symbolic_s,
            factor_s,
            solve_s,
        )?;
    }
    for n in [32usize, 64, 128] {
        let reps = if n >= 128 { 5 } else { 15 };
        let w = SurfaceWeights { wb: 1.0, ws: 0.01 };
        let d0 = bumpy(n);
        let t = Instant::now();
        let mut sys = SurfaceSystem::new(n, n, &w, None)?;
        let symbolic_s = t.elapsed().as_secs_f64();
        let mut v = Vec::new();
        for _ in 0..reps {
            sys.solver = FixedSolver::new(sys.solver.pattern().clone())?;
            let t = Instant::now();
            sys.solver.factor(&sys.a, &sys.fixed)?;
            v.push(t.elapsed().as_secs_f64());
        }
        let factor_s = quartiles(v);
        // One smoother frame: rhs = wq (A d0) with wq = 0.9 (g = 0 here).
        let x0 = sys.columns(&d0);
        let ad = sys.solver.pattern().mul(&sys.a, &x0, 3);
        let rhs: Vec<f64> = ad.iter().map(|v| 0.9 * v).collect();
        let x = sys.solver.solve(&rhs, &x0, 3)?;
        let solve_s = time(reps * 3, || sys.solver.solve(&rhs, &x0, 3).expect("solve"));
        report(
            &out,
            &format!("surface_{n}"),
            &sys.solver,
            3,
            &x,
            symbolic_s,
            factor_s,
            solve_s,
        )?;
    }
    Ok(())
}
