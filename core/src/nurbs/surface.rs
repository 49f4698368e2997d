//! [`NurbsSurface`]: a rational tensor-product B-spline surface with
//! homogeneous control points (The NURBS Book ch. 3-4): evaluation with
//! partial derivatives (A3.6 on the homogeneous surface, then A4.4),
//! exact iso-curves and grid tessellation.

use glam::{DVec3, DVec4};
use serde::{Deserialize, Serialize};

use super::basis::{basis_funs, ders_basis_funs, find_span};
use super::curve::{binomial, euclidean};
use super::{NurbsCurve, NurbsError};

/// A NURBS surface. Control points are stored row by row in `u`:
/// `control[i * n_v + j]` is `P_{i,j}` (`i` along `u`, `j` along `v`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NurbsSurface {
    /// Degree in `u`.
    pub degree_u: usize,
    /// Degree in `v`.
    pub degree_v: usize,
    /// Knot vector in `u`.
    pub knots_u: Vec<f64>,
    /// Knot vector in `v`.
    pub knots_v: Vec<f64>,
    /// Number of control points along `u`.
    pub n_u: usize,
    /// Number of control points along `v`.
    pub n_v: usize,
    /// Homogeneous control points, `n_u * n_v`.
    pub control: Vec<DVec4>,
}

impl NurbsSurface {
    /// A surface after checking sizes, knots and weights.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        degree_u: usize,
        degree_v: usize,
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        n_u: usize,
        n_v: usize,
        control: Vec<DVec4>,
    ) -> Result<Self, NurbsError> {
        if control.len() != n_u * n_v {
            return Err(NurbsError::BadKnots("control net size is not n_u * n_v"));
        }
        let s = Self {
            degree_u,
            degree_v,
            knots_u,
            knots_v,
            n_u,
            n_v,
            control,
        };
        // Knots of each direction through one row and one column. Control
        // weights of a skinned net may in principle be non-positive even
        // though every section's are positive; evaluation checks the
        // weight of each evaluated point instead.
        s.column(0).validate_knots()?;
        s.row(0).validate_knots()?;
        if s.control.iter().any(|c| !c.is_finite()) {
            return Err(NurbsError::NonFinite("control point"));
        }
        Ok(s)
    }

    /// The `v`-direction curve through control points `P_{i, *}`.
    pub fn column(&self, i: usize) -> NurbsCurve {
        NurbsCurve {
            degree: self.degree_v,
            knots: self.knots_v.clone(),
            control: self.control[i * self.n_v..(i + 1) * self.n_v].to_vec(),
        }
    }

    /// The `u`-direction curve through control points `P_{*, j}`.
    pub fn row(&self, j: usize) -> NurbsCurve {
        NurbsCurve {
            degree: self.degree_u,
            knots: self.knots_u.clone(),
            control: (0..self.n_u)
                .map(|i| self.control[i * self.n_v + j])
                .collect(),
        }
    }

    /// Domains `((u0, u1), (v0, v1))`.
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (
            (self.knots_u[self.degree_u], self.knots_u[self.n_u]),
            (self.knots_v[self.degree_v], self.knots_v[self.n_v]),
        )
    }

    /// The exact iso-curve `S(u, v)` for fixed `v`: a curve in `u` with the
    /// surface's `u` degree and knots.
    pub fn iso_curve_v(&self, v: f64) -> NurbsCurve {
        let q = self.degree_v;
        let span = find_span(self.n_v, q, v, &self.knots_v);
        let b = basis_funs(span, v, q, &self.knots_v);
        let control = (0..self.n_u)
            .map(|i| {
                let mut acc = DVec4::ZERO;
                for (j, bj) in b.iter().enumerate() {
                    acc += self.control[i * self.n_v + span - q + j] * *bj;
                }
                acc
            })
            .collect();
        NurbsCurve {
            degree: self.degree_u,
            knots: self.knots_u.clone(),
            control,
        }
    }

    /// The exact iso-curve for fixed `u`: a curve in `v`.
    pub fn iso_curve_u(&self, u: f64) -> NurbsCurve {
        let p = self.degree_u;
        let span = find_span(self.n_u, p, u, &self.knots_u);
        let b = basis_funs(span, u, p, &self.knots_u);
        let control = (0..self.n_v)
            .map(|j| {
                let mut acc = DVec4::ZERO;
                for (i, bi) in b.iter().enumerate() {
                    acc += self.control[(span - p + i) * self.n_v + j] * *bi;
                }
                acc
            })
            .collect();
        NurbsCurve {
            degree: self.degree_v,
            knots: self.knots_v.clone(),
            control,
        }
    }

    /// The point at `(u, v)`.
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        self.iso_curve_v(v).point(u)
    }

    /// Partial derivatives up to total order `d` (A3.6 + A4.4):
    /// `out[k][l]` is d^(k+l) S / du^k dv^l for `k + l <= d`.
    pub fn derivatives(&self, u: f64, v: f64, d: usize) -> Vec<Vec<DVec3>> {
        let (p, q) = (self.degree_u, self.degree_v);
        let su = find_span(self.n_u, p, u, &self.knots_u);
        let sv = find_span(self.n_v, q, v, &self.knots_v);
        let nu = ders_basis_funs(su, u, p, d, &self.knots_u);
        let nv = ders_basis_funs(sv, v, q, d, &self.knots_v);
        // Homogeneous derivatives.
        let mut h = vec![vec![DVec4::ZERO; d + 1]; d + 1];
        for k in 0..=d.min(p) {
            for l in 0..=(d - k).min(q) {
                let mut acc = DVec4::ZERO;
                for r in 0..=p {
                    let mut tmp = DVec4::ZERO;
                    for s in 0..=q {
                        tmp += self.control[(su - p + r) * self.n_v + sv - q + s] * nv[l][s];
                    }
                    acc += tmp * nu[k][r];
                }
                h[k][l] = acc;
            }
        }
        let mut skl = vec![vec![DVec3::ZERO; d + 1]; d + 1];
        for k in 0..=d {
            for l in 0..=(d - k) {
                let mut v = h[k][l].truncate();
                for j in 1..=l {
                    v -= skl[k][l - j] * (binomial(l, j) * h[0][j].w);
                }
                for i in 1..=k {
                    v -= skl[k - i][l] * (binomial(k, i) * h[i][0].w);
                    let mut v2 = DVec3::ZERO;
                    for j in 1..=l {
                        v2 += skl[k - i][l - j] * (binomial(l, j) * h[i][j].w);
                    }
                    v -= v2 * binomial(k, i);
                }
                skl[k][l] = v / h[0][0].w;
            }
        }
        skl
    }

    /// Unit normal `S_u x S_v` at `(u, v)` (zero where degenerate).
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let d = self.derivatives(u, v, 1);
        d[1][0].cross(d[0][1]).normalize_or_zero()
    }

    /// Points on the grid `us x vs`, row-major in `v`:
    /// `out[j * us.len() + i] = S(us[i], vs[j])`. Each row is evaluated on
    /// the exact iso-curve, so the cost is one curve evaluation per point.
    pub fn grid(&self, us: &[f64], vs: &[f64]) -> Vec<DVec3> {
        let mut out = Vec::with_capacity(us.len() * vs.len());
        for &v in vs {
            let c = self.iso_curve_v(v);
            out.extend(us.iter().map(|&u| euclidean(c.point_h(u))));
        }
        out
    }
}
