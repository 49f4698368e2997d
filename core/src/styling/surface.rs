//! Surface tools on uniform bicubic B-spline surfaces (paper §2.3, §4).
//!
//! The surface is `s(u, v) = base(u, v) + Σ N_i(u) N_j(v) d_ij` on
//! `[0, 1]²` with clamped uniform cubic knots: a plain B-spline surface
//! when `base` is zero, and a styled patch of a curve network when `base` is
//! the Coons patch of its boundary curves (the B-spline part then has a
//! zero boundary, so the patch stays G0 to its curves exactly). The
//! internal energy `w_b E_b + w_s E_s` (eq. 9-11) of the whole surface is
//! `dᵀ A d + 2 gᵀ d + k`: `A` is assembled from 1D Gram matrices as Kronecker
//! sums (exact), `g` from the base by 4×4 Gauss quadrature per cell. The
//! three coordinates share `A`, so the solver runs one scalar system with
//! three right-hand sides. The boundary control points are fixed (eq. 7).
//!
//! Equilibrium (eq. 22): the paper adds `-w_q b_q`, `b_q = A c`, to the
//! linear term. We take `b_q` once at activation, so frame `k` gives
//! `d_k = w_q d_0 + (1 - w_q) d_min` with `w_q = f^k`: the smoother
//! (f < 1) converges geometrically to the minimal-energy surface `d_min`,
//! the sharpener (f > 1) extrapolates away from it, bounded by a cap on
//! `w_q`. The matrix never changes during a tool application, so it is
//! factored once per activation and each frame is one solve.

use serde::{Deserialize, Serialize};

use crate::math::DVec3;
use crate::nurbs::{basis_funs, clamped_uniform_knots, ders_basis_funs, find_span};

use super::energy::gauss_on;
use super::solver::{FixedSolver, SymPattern};
use super::StylingError;

/// Value and derivatives of a base surface: `[s, s_u, s_v, s_uu, s_uv, s_vv]`.
pub type BaseDerivs = [DVec3; 6];

/// Weights of the surface internal energy.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SurfaceWeights {
    /// Thin-plate bend weight `w_b` (> 0).
    pub wb: f64,
    /// Membrane stretch weight `w_s` (>= 0).
    pub ws: f64,
}

impl SurfaceWeights {
    /// Checks the weights.
    pub fn validate(&self) -> Result<(), StylingError> {
        if !(self.wb.is_finite() && self.wb > 0.0) {
            return Err(StylingError::BadParameter("surface wb must be > 0"));
        }
        if !(self.ws.is_finite() && self.ws >= 0.0) {
            return Err(StylingError::BadParameter("surface ws must be >= 0"));
        }
        Ok(())
    }
}

/// 1D Gram matrices `G_d[i][k] = ∫ N_i⁽ᵈ⁾ N_k⁽ᵈ⁾` for `d = 0, 1, 2` and
/// mixed `∫ N_i' N_k` is not needed (symmetric terms only).
fn grams(n: usize) -> [Vec<f64>; 3] {
    let knots = clamped_uniform_knots(n, 3);
    let mut g = [vec![0.0; n * n], vec![0.0; n * n], vec![0.0; n * n]];
    for w in knots.windows(2) {
        if w[1] <= w[0] {
            continue;
        }
        for (t, wt) in gauss_on(w[0], w[1]) {
            let span = find_span(n, 3, t, &knots);
            let d = ders_basis_funs(span, t, 3, 2, &knots);
            for a in 0..4 {
                for b in 0..4 {
                    let (i, k) = (span - 3 + a, span - 3 + b);
                    for (o, gm) in g.iter_mut().enumerate() {
                        gm[i * n + k] += wt * d[o][a] * d[o][b];
                    }
                }
            }
        }
    }
    g
}

/// Basis derivatives `(first, ders[0..=2][0..4])` of the clamped uniform
/// cubic basis with `n` functions at `t`.
pub fn basis1(n: usize, t: f64) -> (usize, Vec<Vec<f64>>) {
    let knots = clamped_uniform_knots(n, 3);
    let t = t.clamp(0.0, 1.0);
    let span = find_span(n, 3, t, &knots);
    (span - 3, ders_basis_funs(span, t, 3, 2, &knots))
}

/// The energy of an `n_u × n_v` bicubic surface and its solver.
#[derive(Debug)]
pub struct SurfaceSystem {
    /// Control points along `u`.
    pub n_u: usize,
    /// Control points along `v`.
    pub n_v: usize,
    /// Internal energy matrix values (on the solver's pattern).
    pub a: Vec<f64>,
    /// Linear term `g` of the base, 3 columns of `n_u n_v`.
    pub g: Vec<f64>,
    /// Boundary unknowns.
    pub fixed: Vec<bool>,
    /// The solver (symbolic analysis done once).
    pub solver: FixedSolver,
}

/// The pattern of an `n_u × n_v` bicubic surface (49 neighbours).
pub fn surface_pattern(n_u: usize, n_v: usize) -> SymPattern {
    let mut pairs = Vec::new();
    for i in 0..n_u {
        for j in 0..n_v {
            for k in i.saturating_sub(3)..=(i + 3).min(n_u - 1) {
                for l in j.saturating_sub(3)..=(j + 3).min(n_v - 1) {
                    let (r, c) = (i * n_v + j, k * n_v + l);
                    if r >= c {
                        pairs.push((r, c));
                    }
                }
            }
        }
    }
    SymPattern::new(n_u * n_v, pairs)
}

impl SurfaceSystem {
    /// Assembles `A` and `g` and analyses the pattern.
    pub fn new(
        n_u: usize,
        n_v: usize,
        w: &SurfaceWeights,
        base: Option<&dyn Fn(f64, f64) -> BaseDerivs>,
    ) -> Result<Self, StylingError> {
        if n_u < 4 || n_v < 4 || n_u > 4096 || n_v > 4096 {
            return Err(StylingError::BadParameter(
                "a bicubic surface needs 4..=4096 control points per side",
            ));
        }
        w.validate()?;
        let pattern = surface_pattern(n_u, n_v);
        let (gu, gv) = (grams(n_u), grams(n_v));
        let mut a = vec![0.0; pattern.nnz()];
        for c in 0..pattern.n() {
            let (k, l) = (c / n_v, c % n_v);
            for p in pattern.col_ptr()[c]..pattern.col_ptr()[c + 1] {
                let r = pattern.row_idx()[p];
                let (i, j) = (r / n_v, r % n_v);
                let u = |d: usize| gu[d][i * n_u + k];
                let v = |d: usize| gv[d][j * n_v + l];
                a[p] = w.wb * (u(2) * v(0) + 2.0 * u(1) * v(1) + u(0) * v(2))
                    + w.ws * (u(1) * v(0) + u(0) * v(1));
            }
        }
        let n = n_u * n_v;
        let mut g = vec![0.0; 3 * n];
        if let Some(base) = base {
            let (ku, kv) = (clamped_uniform_knots(n_u, 3), clamped_uniform_knots(n_v, 3));
            for su in ku.windows(2).filter(|s| s[1] > s[0]) {
                for sv in kv.windows(2).filter(|s| s[1] > s[0]) {
                    for (u, wu) in gauss_on(su[0], su[1]) {
                        let (fu, du) = basis1(n_u, u);
                        for (v, wv) in gauss_on(sv[0], sv[1]) {
                            let (fv, dv) = basis1(n_v, v);
                            let b = base(u, v);
                            let wt = wu * wv;
                            for x in 0..4 {
                                for y in 0..4 {
                                    let idx = (fu + x) * n_v + fv + y;
                                    let bend = b[3] * (du[2][x] * dv[0][y])
                                        + b[4] * (2.0 * du[1][x] * dv[1][y])
                                        + b[5] * (du[0][x] * dv[2][y]);
                                    let stretch =
                                        b[1] * (du[1][x] * dv[0][y]) + b[2] * (du[0][x] * dv[1][y]);
                                    let val = (bend * w.wb + stretch * w.ws) * wt;
                                    g[idx] += val.x;
                                    g[n + idx] += val.y;
                                    g[2 * n + idx] += val.z;
                                }
                            }
                        }
                    }
                }
            }
        }
        let mut fixed = vec![false; n];
        for i in 0..n_u {
            for j in 0..n_v {
                if i == 0 || j == 0 || i == n_u - 1 || j == n_v - 1 {
                    fixed[i * n_v + j] = true;
                }
            }
        }
        let solver = FixedSolver::new(pattern)?;
        Ok(Self {
            n_u,
            n_v,
            a,
            g,
            fixed,
            solver,
        })
    }

    /// Column-major (3 columns) unknowns from control points.
    pub fn columns(&self, d: &[[f64; 3]]) -> Vec<f64> {
        let n = d.len();
        let mut x = vec![0.0; 3 * n];
        for (i, p) in d.iter().enumerate() {
            for k in 0..3 {
                x[k * n + i] = p[k];
            }
        }
        x
    }

    fn points(&self, x: &[f64]) -> Vec<[f64; 3]> {
        let n = self.n_u * self.n_v;
        (0..n).map(|i| [x[i], x[n + i], x[2 * n + i]]).collect()
    }

    /// Energy `dᵀ A d + 2 gᵀ d` (without the base's constant).
    pub fn energy(&self, d: &[[f64; 3]]) -> f64 {
        let x = self.columns(d);
        let ax = self.solver.pattern().mul(&self.a, &x, 3);
        x.iter()
            .zip(&ax)
            .zip(&self.g)
            .map(|((xi, ai), gi)| xi * ai + 2.0 * gi * xi)
            .sum()
    }

    /// The minimal-energy control points with the boundary of `d` kept.
    pub fn minimal(&mut self, d: &[[f64; 3]]) -> Result<Vec<[f64; 3]>, StylingError> {
        let a = self.a.clone();
        let fixed = self.fixed.clone();
        self.solver.factor(&a, &fixed)?;
        let rhs: Vec<f64> = self.g.iter().map(|v| -v).collect();
        let x = self.solver.solve(&rhs, &self.columns(d), 3)?;
        Ok(self.points(&x))
    }

    /// Smoother (`f < 1`) or sharpener (`f > 1`, `w_q <= wq_max`) over
    /// `frames` frames from `d0` (§4.1-4.2). Returns the control points
    /// after the last frame and the final `w_q`.
    pub fn equilibrium_frames(
        &mut self,
        d0: &[[f64; 3]],
        f: f64,
        frames: usize,
        wq_max: f64,
    ) -> Result<(Vec<[f64; 3]>, f64), StylingError> {
        let a = self.a.clone();
        let fixed = self.fixed.clone();
        self.solver.factor(&a, &fixed)?;
        let x0 = self.columns(d0);
        // b_q = A d0 + g: the equilibrium of the surface at activation.
        let ad = self.solver.pattern().mul(&self.a, &x0, 3);
        let bq: Vec<f64> = ad.iter().zip(&self.g).map(|(a, g)| a + g).collect();
        let mut wq = 1.0;
        let mut x = x0.clone();
        for _ in 0..frames {
            wq = (wq * f).min(wq_max);
            let rhs: Vec<f64> = bq.iter().zip(&self.g).map(|(b, g)| wq * b - g).collect();
            x = self.solver.solve(&rhs, &x0, 3)?;
        }
        Ok((self.points(&x), wq))
    }

    /// Puller (§4.3): the surface point at `(u0, v0)` attracted to each
    /// target in turn with weight `wpp`, shape kept by the equilibrium of
    /// `d0`. `base0` is the base surface's point at `(u0, v0)`.
    pub fn pull(
        &mut self,
        d0: &[[f64; 3]],
        u0: f64,
        v0: f64,
        base0: DVec3,
        wpp: f64,
        targets: &[DVec3],
    ) -> Result<Vec<[f64; 3]>, StylingError> {
        if !(wpp.is_finite() && wpp > 0.0) {
            return Err(StylingError::BadParameter("wpp must be > 0"));
        }
        let (fu, bu) = point_basis(self.n_u, u0);
        let (fv, bv) = point_basis(self.n_v, v0);
        let mut a = self.a.clone();
        let n = self.n_u * self.n_v;
        let mut idx = Vec::new();
        for x in 0..4 {
            for y in 0..4 {
                idx.push(((fu + x) * self.n_v + fv + y, bu[x] * bv[y]));
            }
        }
        for &(r, nr) in &idx {
            for &(c, nc) in &idx {
                if r >= c {
                    if let Some(s) = self.solver.pattern().slot(r, c) {
                        a[s] += wpp * nr * nc;
                    }
                }
            }
        }
        let fixed = self.fixed.clone();
        self.solver.factor(&a, &fixed)?;
        let x0 = self.columns(d0);
        let ad = self.solver.pattern().mul(&self.a, &x0, 3);
        let mut x = x0.clone();
        for p in targets {
            let q = *p - base0;
            let mut rhs = ad.clone();
            for &(r, nr) in &idx {
                rhs[r] += wpp * nr * q.x;
                rhs[n + r] += wpp * nr * q.y;
                rhs[2 * n + r] += wpp * nr * q.z;
            }
            x = self.solver.solve(&rhs, &x0, 3)?;
        }
        Ok(self.points(&x))
    }
}

/// Basis values `(first, N[0..4])` of the clamped uniform cubic basis.
pub fn point_basis(n: usize, t: f64) -> (usize, Vec<f64>) {
    let knots = clamped_uniform_knots(n, 3);
    let t = t.clamp(0.0, 1.0);
    let span = find_span(n, 3, t, &knots);
    (span - 3, basis_funs(span, t, 3, &knots))
}

/// `Σ N_i(u) N_j(v) d_ij` of an `n_u × n_v` grid.
pub fn eval_grid(n_u: usize, n_v: usize, d: &[[f64; 3]], u: f64, v: f64) -> DVec3 {
    let (fu, bu) = point_basis(n_u, u);
    let (fv, bv) = point_basis(n_v, v);
    let mut p = DVec3::ZERO;
    for x in 0..4 {
        for y in 0..4 {
            p += DVec3::from_array(d[(fu + x) * n_v + fv + y]) * (bu[x] * bv[y]);
        }
    }
    p
}
