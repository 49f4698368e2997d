//! Curve energies as sparse quadratic forms in the control points
//! (paper §2.2 eq. 2-7, §3 eq. 13-20).
//!
//! The unknown is `c`, the control points concatenated as `3 i + axis`.
//! Every term is `∫ w(t) |M (x⁽ᵈ⁾(t) - y(t))|² dt` or a point term
//! `|x(t0) - p|²`, with `M` the identity (point, curve, shape-preserving
//! terms), a line's normal projector or a plane's normal projector, so
//! line and plane attractors couple the coordinates and the system is one
//! `3n × 3n` matrix. The energy is kept as `E = cᵀ A c - 2 rᵀ c + k`, whose
//! minimizer solves `A c = r` (the paper's `b = -2 r`). Integrals use
//! 4-point Gauss-Legendre per knot span (exact for unweighted cubic terms).
//! The pattern couples control points whose supports overlap (`|i - j| <=
//! 3`) in all coordinates, whatever terms are present, so one symbolic
//! factorization serves every frame of a tool.

use crate::math::fm::DetMath as _;
use crate::math::{DMat3, DVec3};

use super::curve::{SplineCurve, DEGREE};
use super::solver::SymPattern;

const GAUSS4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

/// Gauss points `(t, weight)` over every non-empty knot span.
pub fn quadrature_points(knots: &[f64]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for w in knots.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b > a {
            let h = 0.5 * (b - a);
            for (x, wt) in GAUSS4 {
                out.push((a + h * (1.0 + x), h * wt));
            }
        }
    }
    out
}

/// The 1D Gauss points on `[a, b]`.
pub fn gauss_on(a: f64, b: f64) -> [(f64, f64); 4] {
    let h = 0.5 * (b - a);
    GAUSS4.map(|(x, w)| (a + h * (1.0 + x), h * w))
}

/// A local weight function over the normalized parameter `s ∈ [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Weight {
    /// 1 everywhere.
    Uniform,
    /// `exp(-alpha (s - s0)²)` for `|s - s0| <= half_width`, else 0 (paper
    /// eq. 19, truncated so that the curve outside the support is left
    /// exactly as it was).
    Gaussian {
        /// Centre, normalized parameter.
        s0: f64,
        /// Sharpness.
        alpha: f64,
        /// Support half-width, normalized parameter.
        half_width: f64,
    },
    /// `1 / max(gaussian, 1e-3)`: the reciprocal of [`Weight::Gaussian`],
    /// for a shape-preservation term that holds the curve harder away
    /// from `s0` (see `tools`).
    InverseGaussian {
        /// Centre, normalized parameter.
        s0: f64,
        /// Sharpness.
        alpha: f64,
        /// Support half-width, normalized parameter.
        half_width: f64,
    },
}

impl Weight {
    /// A gaussian truncated where it falls below `1e-3`.
    pub fn gaussian(s0: f64, alpha: f64) -> Self {
        Self::Gaussian {
            s0,
            alpha,
            half_width: (1e3f64.fln() / alpha).sqrt(),
        }
    }

    /// Value at normalized parameter `s`.
    pub fn at(&self, s: f64) -> f64 {
        match *self {
            Self::Uniform => 1.0,
            Self::Gaussian {
                s0,
                alpha,
                half_width,
            } => {
                let d = s - s0;
                if d.abs() <= half_width {
                    (-alpha * d * d).fexp()
                } else {
                    0.0
                }
            }
            Self::InverseGaussian {
                s0,
                alpha,
                half_width,
            } => {
                let g = Self::Gaussian {
                    s0,
                    alpha,
                    half_width,
                }
                .at(s);
                1.0 / g.max(1e-3)
            }
        }
    }

    /// The reciprocal weight of a gaussian (identity otherwise).
    pub fn inverse(&self) -> Self {
        match *self {
            Self::Gaussian {
                s0,
                alpha,
                half_width,
            } => Self::InverseGaussian {
                s0,
                alpha,
                half_width,
            },
            w => w,
        }
    }

    /// The normalized interval where the weight is non-zero.
    pub fn support(&self) -> (f64, f64) {
        match *self {
            Self::Uniform => (0.0, 1.0),
            Self::Gaussian { s0, half_width, .. }
            | Self::InverseGaussian { s0, half_width, .. } => (s0 - half_width, s0 + half_width),
        }
    }
}

/// The quadratic form `E = cᵀ A c - 2 rᵀ c` of a curve's control points.
#[derive(Clone, Debug)]
pub struct CurveSystem {
    /// The sparsity pattern (`3n` unknowns).
    pub pattern: SymPattern,
    /// Matrix values on the pattern.
    pub values: Vec<f64>,
    /// Right-hand side `r` (`A c = r` at the minimum).
    pub rhs: Vec<f64>,
    knots: Vec<f64>,
    n: usize,
}

/// The pattern of a curve of `n` control points.
pub fn curve_pattern(n: usize) -> SymPattern {
    let mut pairs = Vec::new();
    for i in 0..n {
        for j in i.saturating_sub(DEGREE)..=i {
            for a in 0..3 {
                for b in 0..3 {
                    pairs.push((3 * i + a, 3 * j + b));
                }
            }
        }
    }
    SymPattern::new(3 * n, pairs)
}

impl CurveSystem {
    /// An empty (zero) energy for curves with the knots of `curve`, on a
    /// given pattern (see [`curve_pattern`]).
    pub fn new(curve: &SplineCurve, pattern: SymPattern) -> Self {
        let nnz = pattern.nnz();
        Self {
            values: vec![0.0; nnz],
            rhs: vec![0.0; 3 * curve.n()],
            pattern,
            knots: curve.knots.clone(),
            n: curve.n(),
        }
    }

    fn norm(&self, t: f64) -> f64 {
        let a = self.knots[DEGREE];
        let b = self.knots[self.n];
        (t - a) / (b - a)
    }

    fn add_outer(&mut self, first: usize, n: &[f64], m: &DMat3, scale: f64) {
        for (i, ni) in n.iter().enumerate() {
            for (j, nj) in n.iter().enumerate().take(i + 1) {
                let f = scale * ni * nj;
                if f == 0.0 {
                    continue;
                }
                let (ci, cj) = (first + i, first + j);
                for a in 0..3 {
                    for b in 0..3 {
                        let (r, c) = (3 * ci + a, 3 * cj + b);
                        if ci == cj && r < c {
                            continue;
                        }
                        if let Some(k) = self.pattern.slot(r, c) {
                            self.values[k] += f * m.col(b)[a];
                        }
                    }
                }
            }
        }
    }

    fn add_linear(&mut self, first: usize, n: &[f64], v: DVec3, scale: f64) {
        for (i, ni) in n.iter().enumerate() {
            let f = scale * ni;
            let c = first + i;
            self.rhs[3 * c] += f * v.x;
            self.rhs[3 * c + 1] += f * v.y;
            self.rhs[3 * c + 2] += f * v.z;
        }
    }

    /// `scale ∫ w(s) |M (x⁽ᵈ⁾(t) - target(t))|² dt` with `M` symmetric
    /// idempotent or identity (`None` target means 0).
    pub fn add_integral(
        &mut self,
        d: usize,
        weight: Weight,
        m: DMat3,
        scale: f64,
        target: Option<&dyn Fn(f64) -> DVec3>,
    ) {
        let curve_knots = self.knots.clone();
        let shell = SplineCurve {
            knots: curve_knots.clone(),
            ctrl: vec![[0.0; 3]; self.n],
        };
        for (t, wq) in quadrature_points(&curve_knots) {
            let w = weight.at(self.norm(t)) * wq * scale;
            if w == 0.0 {
                continue;
            }
            let (first, ders) = shell.basis_ders(t, d);
            let nd = ders[d].clone();
            self.add_outer(first, &nd, &m, w);
            if let Some(f) = target {
                let y = m * f(t);
                self.add_linear(first, &nd, y, w);
            }
        }
    }

    /// Bend energy `wb ∫ w |x''|²` (eq. 2, local form eq. 17).
    pub fn add_bend(&mut self, wb: f64, weight: Weight) {
        self.add_integral(2, weight, DMat3::IDENTITY, wb, None);
    }

    /// Stretch energy `ws ∫ w |x'|²` (eq. 3, local form eq. 17).
    pub fn add_stretch(&mut self, ws: f64, weight: Weight) {
        self.add_integral(1, weight, DMat3::IDENTITY, ws, None);
    }

    /// Shape preservation against `reference` (same knots):
    /// `w ∫ |x⁽ᵈ⁾ - x_ref⁽ᵈ⁾|²` (eq. 13 for d = 0, eq. 14 for d = 1).
    pub fn add_shape(&mut self, d: usize, w: f64, reference: &SplineCurve) {
        self.add_shape_weighted(d, w, Weight::Uniform, reference);
    }

    /// Shape preservation with a weight function over the parameter.
    pub fn add_shape_weighted(
        &mut self,
        d: usize,
        w: f64,
        weight: Weight,
        reference: &SplineCurve,
    ) {
        let f = |t: f64| reference.derivs(t, d)[d];
        self.add_integral(d, weight, DMat3::IDENTITY, w, Some(&f));
    }

    /// Point attractor `w ∫ weight |x - p|²`.
    pub fn add_point_attractor(&mut self, w: f64, weight: Weight, p: DVec3) {
        let f = move |_t: f64| p;
        self.add_integral(0, weight, DMat3::IDENTITY, w, Some(&f));
    }

    /// Line attractor `w ∫ weight dist(x, line)²` (line through `a` along `dir`).
    pub fn add_line_attractor(&mut self, w: f64, weight: Weight, a: DVec3, dir: DVec3) {
        let d = dir.normalize();
        let m = DMat3::IDENTITY - outer(d, d);
        let f = move |_t: f64| a;
        self.add_integral(0, weight, m, w, Some(&f));
    }

    /// Plane attractor `w ∫ weight dist(x, plane)²` (plane through `a`, normal `n`).
    pub fn add_plane_attractor(&mut self, w: f64, weight: Weight, a: DVec3, n: DVec3) {
        let n = n.normalize();
        let m = outer(n, n);
        let f = move |_t: f64| a;
        self.add_integral(0, weight, m, w, Some(&f));
    }

    /// Curve attractor `w ∫ weight |x(t) - y(s(t))|²`, with `y`'s
    /// parameter mapped linearly from this curve's domain.
    pub fn add_curve_attractor(&mut self, w: f64, weight: Weight, y: &SplineCurve) {
        let (a, b) = (self.knots[DEGREE], self.knots[self.n]);
        let (ya, yb) = y.domain();
        let f = move |t: f64| y.point(ya + (yb - ya) * (t - a) / (b - a));
        self.add_integral(0, weight, DMat3::IDENTITY, w, Some(&f));
    }

    /// Point-to-point attractor `w |x(t0) - p|²` (eq. 20).
    pub fn add_point_to_point(&mut self, w: f64, t0: f64, p: DVec3) {
        let shell = SplineCurve {
            knots: self.knots.clone(),
            ctrl: vec![[0.0; 3]; self.n],
        };
        let (first, b) = shell.basis(t0);
        self.add_outer(first, &b, &DMat3::IDENTITY, w);
        self.add_linear(first, &b, p, w);
    }

    /// `E(c) = cᵀ A c - 2 rᵀ c` (without the constant).
    pub fn energy(&self, c: &[f64]) -> f64 {
        let ac = self.pattern.mul(&self.values, c, 1);
        c.iter()
            .zip(&ac)
            .zip(&self.rhs)
            .map(|((ci, ai), ri)| ci * ai - 2.0 * ri * ci)
            .sum()
    }
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Flattens control points to the unknown vector.
pub fn flatten(ctrl: &[[f64; 3]]) -> Vec<f64> {
    ctrl.iter().flatten().copied().collect()
}

/// Unflattens the unknown vector.
pub fn unflatten(c: &[f64]) -> Vec<[f64; 3]> {
    c.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect()
}
