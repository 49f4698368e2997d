//! [`NurbsCurve`]: a rational B-spline curve with homogeneous control
//! points (The NURBS Book ch. 2-5): evaluation with derivatives (A3.2, A4.2),
//! knot insertion (Boehm's single insertion, repeated), knot refinement,
//! Bézier decomposition and degree elevation.
//!
//! Degree elevation is done by Bézier decomposition, elevation of each
//! segment and re-assembly (P&T §5.5, the first method): the geometry and
//! parameterization are exactly preserved; interior knots come out with
//! multiplicity equal to the new degree (C0 representation), which costs a
//! few control points and no accuracy. Knot removal to restore continuity
//! is not done.

use glam::{DAffine3, DVec3, DVec4};
use serde::{Deserialize, Serialize};

use super::basis::{basis_funs, ders_basis_funs, find_span, knot_multiplicities};
use super::NurbsError;

/// A NURBS curve: degree, clamped or unclamped knot vector and homogeneous
/// control points `(w x, w y, w z, w)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct NurbsCurve {
    /// Degree `p >= 1`.
    #[schemars(range(min = 1, max = 7))]
    pub degree: usize,
    /// Knot vector, `control.len() + degree + 1` non-decreasing values.
    pub knots: Vec<f64>,
    /// Homogeneous control points (`xyz` premultiplied by the weight `w`).
    #[schemars(with = "Vec<[f64; 4]>")]
    pub control: Vec<DVec4>,
}

/// Binomial coefficient as f64 (small arguments).
pub(crate) fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let mut r = 1.0;
    for i in 0..k.min(n - k) {
        r = r * (n - i) as f64 / (i + 1) as f64;
    }
    r
}

/// A homogeneous point from a Euclidean point and weight.
pub fn homogeneous(p: DVec3, w: f64) -> DVec4 {
    DVec4::new(p.x * w, p.y * w, p.z * w, w)
}

/// The Euclidean point of a homogeneous point.
pub fn euclidean(h: DVec4) -> DVec3 {
    DVec3::new(h.x / h.w, h.y / h.w, h.z / h.w)
}

impl NurbsCurve {
    /// A curve after checking degree, knots and weights.
    pub fn new(degree: usize, knots: Vec<f64>, control: Vec<DVec4>) -> Result<Self, NurbsError> {
        let c = Self {
            degree,
            knots,
            control,
        };
        c.validate()?;
        Ok(c)
    }

    /// A non-rational curve (all weights 1).
    pub fn from_points(
        degree: usize,
        knots: Vec<f64>,
        points: &[DVec3],
    ) -> Result<Self, NurbsError> {
        Self::new(
            degree,
            knots,
            points.iter().map(|p| homogeneous(*p, 1.0)).collect(),
        )
    }

    /// Checks the invariants: degree, knot count and order, non-empty
    /// domain, finite coordinates and positive weights.
    pub fn validate(&self) -> Result<(), NurbsError> {
        self.validate_knots()?;
        for (i, c) in self.control.iter().enumerate() {
            if !c.is_finite() {
                return Err(NurbsError::NonFinite("control point"));
            }
            if !(c.w > 0.0) {
                return Err(NurbsError::BadWeight {
                    index: i,
                    weight: c.w,
                });
            }
        }
        Ok(())
    }

    /// Checks degree and knot vector only (not the weights).
    pub fn validate_knots(&self) -> Result<(), NurbsError> {
        let n = self.control.len();
        if self.degree == 0 || n < self.degree + 1 {
            return Err(NurbsError::BadDegree {
                degree: self.degree,
                n_ctrl: n,
            });
        }
        if self.knots.len() != n + self.degree + 1 {
            return Err(NurbsError::BadKnots("length is not n_ctrl + degree + 1"));
        }
        if self.knots.iter().any(|k| !k.is_finite()) {
            return Err(NurbsError::NonFinite("knot"));
        }
        if self.knots.windows(2).any(|w| w[1] < w[0]) {
            return Err(NurbsError::BadKnots("decreasing"));
        }
        let (a, b) = self.domain();
        if !(b > a) {
            return Err(NurbsError::BadKnots("empty domain"));
        }
        Ok(())
    }

    /// The parameter domain `[knots[p], knots[n]]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.control.len()])
    }

    /// The homogeneous point at `u` (A4.1 without the division).
    pub fn point_h(&self, u: f64) -> DVec4 {
        let p = self.degree;
        let span = find_span(self.control.len(), p, u, &self.knots);
        let b = basis_funs(span, u, p, &self.knots);
        let mut acc = DVec4::ZERO;
        for (j, bj) in b.iter().enumerate() {
            acc += self.control[span - p + j] * *bj;
        }
        acc
    }

    /// The point at `u`.
    pub fn point(&self, u: f64) -> DVec3 {
        euclidean(self.point_h(u))
    }

    /// Derivatives of the homogeneous curve up to order `d` (A3.2).
    pub fn derivatives_h(&self, u: f64, d: usize) -> Vec<DVec4> {
        let p = self.degree;
        let span = find_span(self.control.len(), p, u, &self.knots);
        let nd = ders_basis_funs(span, u, p, d, &self.knots);
        (0..=d)
            .map(|k| {
                if k > p {
                    return DVec4::ZERO;
                }
                let mut acc = DVec4::ZERO;
                for j in 0..=p {
                    acc += self.control[span - p + j] * nd[k][j];
                }
                acc
            })
            .collect()
    }

    /// The point and its derivatives up to order `d` (A4.2): `out[0]` is
    /// the point, `out[k]` the k-th derivative.
    pub fn derivatives(&self, u: f64, d: usize) -> Vec<DVec3> {
        let h = self.derivatives_h(u, d);
        let w0 = h[0].w;
        let mut ck: Vec<DVec3> = Vec::with_capacity(d + 1);
        for k in 0..=d {
            let mut v = h[k].truncate();
            for i in 1..=k {
                v -= ck[k - i] * (binomial(k, i) * h[i].w);
            }
            ck.push(v / w0);
        }
        ck
    }

    /// The unit tangent at `u` (zero when the derivative vanishes).
    pub fn tangent(&self, u: f64) -> DVec3 {
        self.derivatives(u, 1)[1].normalize_or_zero()
    }

    /// Inserts the knot `u` once (Boehm). `u` must lie strictly inside the
    /// domain or at an interior knot.
    pub fn insert_knot(&mut self, u: f64) {
        let p = self.degree;
        let n = self.control.len();
        let k = find_span(n, p, u, &self.knots);
        let mut q = Vec::with_capacity(n + 1);
        for i in 0..=n {
            if i + p <= k {
                q.push(self.control[i]);
            } else if i > k {
                q.push(self.control[i - 1]);
            } else {
                let den = self.knots[i + p] - self.knots[i];
                let a = if den == 0.0 {
                    0.0
                } else {
                    (u - self.knots[i]) / den
                };
                q.push(self.control[i] * a + self.control[i - 1] * (1.0 - a));
            }
        }
        self.knots.insert(k + 1, u);
        self.control = q;
    }

    /// Inserts `u` until its multiplicity is at least `mult` (at most the degree).
    pub fn insert_knot_to_multiplicity(&mut self, u: f64, mult: usize) {
        let have = self.knots.iter().filter(|&&k| k == u).count();
        for _ in have..mult.min(self.degree) {
            self.insert_knot(u);
        }
    }

    /// Refines the knot vector so that every value of `target` appears with
    /// at least its multiplicity there (knot refinement by repeated
    /// insertion). Values outside the open domain are ignored.
    pub fn refine_to(&mut self, target: &[f64]) {
        let (a, b) = self.domain();
        for (v, m) in knot_multiplicities(target) {
            if v > a && v < b {
                let have = self.knots.iter().filter(|&&k| k == v).count();
                for _ in have..m {
                    self.insert_knot(v);
                }
            }
        }
    }

    /// The Bézier segments of the curve (each `degree + 1` homogeneous
    /// points) with their parameter intervals. Works on clamped curves.
    pub fn bezier_segments(&self) -> Vec<((f64, f64), Vec<DVec4>)> {
        let p = self.degree;
        let mut c = self.clamped();
        let (a, b) = c.domain();
        let interior: Vec<f64> = knot_multiplicities(&c.knots)
            .into_iter()
            .map(|(v, _)| v)
            .filter(|v| *v > a && *v < b)
            .collect();
        for v in &interior {
            c.insert_knot_to_multiplicity(*v, p);
        }
        let mut bounds = vec![a];
        bounds.extend(interior);
        bounds.push(b);
        // Clamped, with every interior knot of multiplicity p: segment s
        // starts at control point s*p.
        bounds
            .windows(2)
            .enumerate()
            .map(|(s, w)| {
                let i0 = s * p;
                ((w[0], w[1]), c.control[i0..i0 + p + 1].to_vec())
            })
            .collect()
    }

    /// The same curve with degree raised by `t` (exact; see module doc).
    pub fn elevate_degree(&self, t: usize) -> Self {
        if t == 0 {
            return self.clone();
        }
        let p = self.degree;
        let ph = p + t;
        let segs = self.bezier_segments();
        let mut control: Vec<DVec4> = Vec::new();
        let mut knots = vec![segs[0].0 .0; ph + 1];
        for (s, ((_, b), pts)) in segs.iter().enumerate() {
            let elevated: Vec<DVec4> = (0..=ph)
                .map(|i| {
                    let lo = i.saturating_sub(t);
                    let hi = p.min(i);
                    let mut acc = DVec4::ZERO;
                    for (j, pj) in pts.iter().enumerate().take(hi + 1).skip(lo) {
                        acc += *pj * (binomial(p, j) * binomial(t, i - j) / binomial(ph, i));
                    }
                    acc
                })
                .collect();
            if s == 0 {
                control.extend(elevated);
            } else {
                control.extend(elevated.into_iter().skip(1));
            }
            let reps = if s + 1 == segs.len() { ph + 1 } else { ph };
            knots.extend(std::iter::repeat_n(*b, reps));
        }
        Self {
            degree: ph,
            knots,
            control,
        }
    }

    /// True when the knot vector has `degree + 1` equal knots at both ends.
    pub fn is_clamped(&self) -> bool {
        let p = self.degree;
        let m = self.knots.len();
        self.knots[..=p].iter().all(|k| *k == self.knots[0])
            && self.knots[m - p - 1..]
                .iter()
                .all(|k| *k == self.knots[m - 1])
    }

    /// Converts an unclamped (e.g. periodic) curve into the clamped curve
    /// with the same shape on its domain, by inserting the domain ends
    /// until they have multiplicity `degree` and dropping the outside part.
    pub fn clamped(&self) -> Self {
        if self.is_clamped() {
            return self.clone();
        }
        let p = self.degree;
        let (a, b) = self.domain();
        let mut c = self.clone();
        for v in [a, b] {
            let have = c.knots.iter().filter(|&&k| k == v).count();
            for _ in have..p {
                c.insert_knot(v);
            }
        }
        let s = c.knots.iter().position(|&k| k == a).unwrap_or(0);
        let e = c.knots.iter().position(|&k| k == b).unwrap_or(0);
        let control = c.control[s - 1..e].to_vec();
        let mut knots = vec![a];
        knots.extend_from_slice(&c.knots[s..e + p]);
        knots.push(b);
        Self {
            degree: p,
            knots,
            control,
        }
    }

    /// Reparameterizes linearly onto `[a, b]` (shape unchanged). The
    /// domain ends map exactly onto `a` and `b`.
    pub fn with_domain(&self, a: f64, b: f64) -> Self {
        let (a0, b0) = self.domain();
        let s = (b - a) / (b0 - a0);
        let mut c = self.clone();
        for k in &mut c.knots {
            *k = if *k == a0 {
                a
            } else if *k == b0 {
                b
            } else {
                a + (*k - a0) * s
            };
        }
        c
    }

    /// The curve traversed backwards (parameter `a + b - u`).
    pub fn reversed(&self) -> Self {
        let (a, b) = self.domain();
        let mut knots: Vec<f64> = self.knots.iter().rev().map(|k| a + b - k).collect();
        let p = self.degree;
        let n = self.control.len();
        knots[p] = a;
        knots[n] = b;
        Self {
            degree: p,
            knots,
            control: self.control.iter().rev().copied().collect(),
        }
    }

    /// The curve with every control point mapped by an affine map (exact for
    /// rational curves: the map acts on Euclidean points, weights stay).
    pub fn transformed(&self, m: &DAffine3) -> Self {
        let mut c = self.clone();
        for h in &mut c.control {
            *h = homogeneous(m.transform_point3(euclidean(*h)), h.w);
        }
        c
    }

    /// Points at `n + 1` equally spaced parameters over the domain.
    pub fn polyline(&self, n: usize) -> Vec<DVec3> {
        let (a, b) = self.domain();
        (0..=n)
            .map(|i| self.point(a + (b - a) * i as f64 / n as f64))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::basis::clamped_uniform_knots;

    fn sample() -> NurbsCurve {
        let pts = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(3.0, 2.5, 1.0),
            DVec3::new(4.0, 0.0, -1.0),
            DVec3::new(6.0, 1.0, 0.0),
            DVec3::new(7.0, 3.0, 2.0),
        ];
        let mut c = NurbsCurve::from_points(3, clamped_uniform_knots(6, 3), &pts).unwrap();
        c.control[2] = homogeneous(euclidean(c.control[2]), 2.5);
        c
    }

    #[test]
    fn insertion_and_elevation_keep_the_curve() {
        let c = sample();
        let mut d = c.clone();
        d.insert_knot(0.3);
        d.insert_knot(0.3);
        d.insert_knot(0.77);
        let e = c.elevate_degree(2);
        assert_eq!(e.degree, 5);
        for i in 0..=100 {
            let u = i as f64 / 100.0;
            assert!((c.point(u) - d.point(u)).length() < 1e-12);
            assert!((c.point(u) - e.point(u)).length() < 1e-12);
        }
    }

    #[test]
    fn rational_derivative_matches_finite_difference() {
        let c = sample();
        let h = 1e-6;
        for u in [0.1, 0.42, 0.9] {
            let d = c.derivatives(u, 2);
            let fd = (c.point(u + h) - c.point(u - h)) / (2.0 * h);
            assert!((fd - d[1]).length() < 1e-5 * d[1].length().max(1.0));
            let fd2 = (c.derivatives(u + h, 1)[1] - c.derivatives(u - h, 1)[1]) / (2.0 * h);
            assert!((fd2 - d[2]).length() < 1e-4 * d[2].length().max(1.0));
        }
    }
}
