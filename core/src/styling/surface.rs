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

use crate::math::{DVec2, DVec3};
use crate::nurbs::{basis_funs, clamped_uniform_knots, ders_basis_funs, find_span};

use super::budget::Budget;
use super::energy::gauss_on;
use super::jet::{Jet, VJet};
use super::polygon::NgonDomain;
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
    /// The polygon of an n-sided patch (`None`: the unit square, whose
    /// boundary control points are fixed).
    domain: Option<NgonDomain>,
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
            domain: None,
        })
    }

    /// The energy of the weighted displacement `w(p) Σ N_i(x) N_j(y) d_ij`
    /// of an n-sided patch (`n × n` coefficients over the unit square
    /// around `domain`), integrated over the polygon, with the base surface
    /// `base` (value and derivatives at a domain point). Coefficients whose
    /// Greville point lies outside the polygon are fixed (at zero).
    pub fn on_ngon(
        n: usize,
        domain: &NgonDomain,
        w: &SurfaceWeights,
        base: &dyn Fn(DVec2) -> VJet,
    ) -> Result<Self, StylingError> {
        if !(4..=4096).contains(&n) {
            return Err(StylingError::BadParameter(
                "a bicubic surface needs 4..=4096 control points per side",
            ));
        }
        w.validate()?;
        let pattern = surface_pattern(n, n);
        let mut a = vec![0.0; pattern.nnz()];
        let count = n * n;
        let mut g = vec![0.0; 3 * count];
        let knots = clamped_uniform_knots(n, 3);
        let spans: Vec<(f64, f64)> = knots
            .windows(2)
            .filter(|s| s[1] > s[0])
            .map(|s| (s[0], s[1]))
            .collect();
        let mut slots = vec![0usize; 16 * 16];
        for &(x0, x1) in &spans {
            for &(y0, y1) in &spans {
                let quad = domain.cell_quadrature(x0, x1, y0, y1);
                if quad.is_empty() {
                    continue;
                }
                let mid = DVec2::new(0.5 * (x0 + x1), 0.5 * (y0 + y1));
                let (fu, _) = basis1(n, mid.x);
                let (fv, _) = basis1(n, mid.y);
                let idx = |l: usize| (fu + l / 4) * n + fv + l % 4;
                for r in 0..16 {
                    for c in 0..=r {
                        slots[r * 16 + c] = pattern.slot(idx(r), idx(c)).unwrap_or(usize::MAX);
                    }
                }
                for (p, wt) in quad {
                    let (_, du) = basis1_in(n, p.x, fu);
                    let (_, dv) = basis1_in(n, p.y, fv);
                    let wj = NgonDomain::weight(&domain.dists(p));
                    let phi: Vec<Jet> = (0..16)
                        .map(|l| {
                            let (x, y) = (l / 4, l % 4);
                            let b = Jet {
                                v: du[0][x] * dv[0][y],
                                x: du[1][x] * dv[0][y],
                                y: du[0][x] * dv[1][y],
                                xx: du[2][x] * dv[0][y],
                                xy: du[1][x] * dv[1][y],
                                yy: du[0][x] * dv[2][y],
                            };
                            b * wj
                        })
                        .collect();
                    for r in 0..16 {
                        for c in 0..=r {
                            let (pr, pc) = (phi[r], phi[c]);
                            let val = w.wb * (pr.xx * pc.xx + 2.0 * pr.xy * pc.xy + pr.yy * pc.yy)
                                + w.ws * (pr.x * pc.x + pr.y * pc.y);
                            let s = slots[r * 16 + c];
                            if s != usize::MAX {
                                a[s] += wt * val;
                            }
                        }
                    }
                    let b = base(p);
                    for (l, ph) in phi.iter().enumerate() {
                        let bend = b.xx * ph.xx + b.xy * (2.0 * ph.xy) + b.yy * ph.yy;
                        let stretch = b.x * ph.x + b.y * ph.y;
                        let val = (bend * w.wb + stretch * w.ws) * wt;
                        let i = idx(l);
                        g[i] += val.x;
                        g[count + i] += val.y;
                        g[2 * count + i] += val.z;
                    }
                }
            }
        }
        let greville = |i: usize| (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0;
        let fixed: Vec<bool> = (0..count)
            .map(|l| !domain.contains(DVec2::new(greville(l / n), greville(l % n)), -1e-9))
            .collect();
        if a.iter().chain(&g).any(|v| !v.is_finite()) {
            return Err(StylingError::NonFinite("n-sided patch energy"));
        }
        let solver = FixedSolver::new(pattern)?;
        Ok(Self {
            n_u: n,
            n_v: n,
            a,
            g,
            fixed,
            solver,
            domain: Some(domain.clone()),
        })
    }

    /// The displacement basis at `(u, v)`: `(unknown, value)` pairs.
    pub fn point_row(&self, u: f64, v: f64) -> Result<Vec<(usize, f64)>, StylingError> {
        let (fu, bu) = point_basis(self.n_u, u);
        let (fv, bv) = point_basis(self.n_v, v);
        let scale = match &self.domain {
            None => 1.0,
            Some(dom) => {
                let p = DVec2::new(u, v);
                if !dom.contains(p, 0.0) {
                    return Err(StylingError::BadParameter(
                        "(u0, v0) lies outside the n-sided patch's domain (the regular n-gon inscribed in the unit square)",
                    ));
                }
                NgonDomain::weight(&dom.dists(p)).v
            }
        };
        let mut idx = Vec::with_capacity(16);
        for x in 0..4 {
            for y in 0..4 {
                let b = bu[x] * bv[y];
                idx.push((
                    (fu + x) * self.n_v + fv + y,
                    if self.domain.is_some() { b * scale } else { b },
                ));
            }
        }
        Ok(idx)
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

    /// The global smoother (`f < 1`) or sharpener (`f > 1`, `w_q <=
    /// wq_max`) over `frames` frames from `d0` (§4.1-4.2): `d_min + w_q (d0
    /// - d_min)` with `w_q = min(f^frames, wq_max)`, the minimal-energy
    /// `d_min` from one factorization. Returns the control points and the
    /// final `w_q`. (The held tools of the ops, local and bounded, are in
    /// [`super::surface_hold`].)
    pub fn equilibrium_frames(
        &mut self,
        d0: &[[f64; 3]],
        f: f64,
        frames: usize,
        wq_max: f64,
    ) -> Result<(Vec<[f64; 3]>, f64), StylingError> {
        Budget::default().check_tool_work("path", frames, self.n_u * self.n_v)?;
        let dmin = self.minimal(d0)?;
        let mut wq = 1.0;
        for _ in 0..frames {
            wq = (wq * f).min(wq_max);
        }
        let d = d0
            .iter()
            .zip(&dmin)
            .map(|(a, m)| {
                let (a, m) = (DVec3::from_array(*a), DVec3::from_array(*m));
                (m + (a - m) * wq).to_array()
            })
            .collect();
        Ok((d, wq))
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
        let (d, _) = self.pull_guarded(d0, u0, v0, base0, wpp, targets, &mut |_| true)?;
        Ok(d)
    }

    /// [`Self::pull`], stopping at the first frame whose control points
    /// `accept` refuses (taken as far towards its target as is accepted:
    /// half, a quarter or an eighth of the way); returns the control points
    /// after the last frame taken and how many frames were taken.
    #[allow(clippy::too_many_arguments)]
    pub fn pull_guarded(
        &mut self,
        d0: &[[f64; 3]],
        u0: f64,
        v0: f64,
        base0: DVec3,
        wpp: f64,
        targets: &[DVec3],
        accept: &mut dyn FnMut(&[[f64; 3]]) -> bool,
    ) -> Result<(Vec<[f64; 3]>, usize), StylingError> {
        if !(wpp.is_finite() && wpp > 0.0) {
            return Err(StylingError::BadParameter("wpp must be > 0"));
        }
        let budget = Budget::default();
        budget.check_extent("path", targets)?;
        budget.check_tool_work("path", targets.len(), self.n_u * self.n_v)?;
        let idx = self.point_row(u0, v0)?;
        let mut a = self.a.clone();
        let n = self.n_u * self.n_v;
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
        let mut last = d0.to_vec();
        // The displacement the pulled point has now: a refused frame is
        // retried towards its target from here (half, quarter, eighth).
        let mut from = idx.iter().fold(DVec3::ZERO, |acc, &(r, nr)| {
            acc + DVec3::new(x0[r], x0[n + r], x0[2 * n + r]) * nr
        });
        for (frame, p) in targets.iter().enumerate() {
            let target = *p - base0;
            let mut part = 1.0;
            loop {
                let q = from + (target - from) * part;
                let mut rhs = ad.clone();
                for &(r, nr) in &idx {
                    rhs[r] += wpp * nr * q.x;
                    rhs[n + r] += wpp * nr * q.y;
                    rhs[2 * n + r] += wpp * nr * q.z;
                }
                let x = self.solver.solve(&rhs, &x0, 3)?;
                let d = self.points(&x);
                if accept(&d) {
                    last = d;
                    from = q;
                    break;
                }
                part *= 0.5;
                if part < 0.1 {
                    return Ok((last, frame));
                }
            }
            if part < 1.0 {
                return Ok((last, frame + 1));
            }
        }
        Ok((last, targets.len()))
    }
}

/// [`basis1`] at `t` in the span whose first function is `first` (a
/// quadrature point on a cell's edge stays in that cell's span).
fn basis1_in(n: usize, t: f64, first: usize) -> (usize, Vec<Vec<f64>>) {
    let knots = clamped_uniform_knots(n, 3);
    let t = t.clamp(0.0, 1.0);
    let span = first + 3;
    (first, ders_basis_funs(span, t, 3, 2, &knots))
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
