//! Curve fitting (The NURBS Book ch. 9): parameter choice (§9.2.1),
//! global interpolation (A9.1), closed periodic interpolation, natural
//! cubic interpolation at given parameters, and least-squares
//! approximation (§9.4.1) to a tolerance.
//!
//! The natural cubic interpolant (knots at the data parameters, zero second
//! derivative at both ends) is what lofting uses in `v`: adding a data
//! point that lies on the curve leaves the curve unchanged (the old curve
//! is in the refined spline space and meets every condition, and the
//! solution is unique), which is exactly the "insert a key section without
//! changing the shape" edit of the GC paper.

use glam::{DVec3, DVec4};
use serde::{Deserialize, Serialize};

use super::basis::{averaged_knots, basis_funs, ders_basis_funs, find_span};
use super::curve::homogeneous;
use super::linalg::solve;
use super::{NurbsCurve, NurbsError};

/// How data points are given parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ParamMethod {
    /// Proportional to chord lengths (eq. 9.5).
    #[default]
    ChordLength,
    /// Proportional to square roots of chord lengths (eq. 9.6), better at
    /// sharp turns.
    Centripetal,
    /// Equally spaced.
    Uniform,
}

fn check_points(points: &[DVec3], need: usize) -> Result<(), NurbsError> {
    if points.len() < need {
        return Err(NurbsError::TooFewPoints {
            got: points.len(),
            need,
        });
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(NurbsError::NonFinite("data point"));
    }
    Ok(())
}

/// Parameters in `[0, 1]` for open data (`closed = false`: `points.len()`
/// values from 0 to 1) or closed data (`closed = true`: `points.len() + 1`
/// values, the last for the return to the first point).
pub fn parameters(
    points: &[DVec3],
    method: ParamMethod,
    closed: bool,
) -> Result<Vec<f64>, NurbsError> {
    let n = points.len();
    let segs = if closed { n } else { n - 1 };
    let mut d = Vec::with_capacity(segs);
    for i in 0..segs {
        let j = (i + 1) % n;
        let len = (points[j] - points[i]).length();
        if !(len > 0.0) {
            return Err(NurbsError::CoincidentPoints(i, j));
        }
        d.push(match method {
            ParamMethod::ChordLength => len,
            ParamMethod::Centripetal => len.sqrt(),
            ParamMethod::Uniform => 1.0,
        });
    }
    let total: f64 = d.iter().sum();
    let mut t = Vec::with_capacity(segs + 1);
    t.push(0.0);
    let mut acc = 0.0;
    for (i, di) in d.iter().enumerate() {
        acc += di;
        t.push(if i + 1 == segs { 1.0 } else { acc / total });
    }
    Ok(t)
}

/// Global interpolation (A9.1): the non-rational curve of degree
/// `min(degree, n - 1)` through `points`, with averaged knots.
pub fn interpolate(
    points: &[DVec3],
    degree: usize,
    method: ParamMethod,
) -> Result<NurbsCurve, NurbsError> {
    check_points(points, 2)?;
    let params = parameters(points, method, false)?;
    interpolate_at(points, &params, degree)
}

/// Global interpolation at given strictly increasing parameters.
pub fn interpolate_at(
    points: &[DVec3],
    params: &[f64],
    degree: usize,
) -> Result<NurbsCurve, NurbsError> {
    check_points(points, 2)?;
    check_params(params, points.len())?;
    let p = degree.min(points.len() - 1).max(1);
    let knots = averaged_knots(params, p);
    let n = points.len();
    let mut a = vec![0.0; n * n];
    for (r, &t) in params.iter().enumerate() {
        let span = find_span(n, p, t, &knots);
        let b = basis_funs(span, t, p, &knots);
        for (j, bj) in b.iter().enumerate() {
            a[r * n + span - p + j] = *bj;
        }
    }
    let ctrl = solve(a, points.to_vec())?;
    NurbsCurve::from_points(p, knots, &ctrl)
}

fn check_params(params: &[f64], n: usize) -> Result<(), NurbsError> {
    if params.len() != n {
        return Err(NurbsError::ParamCount {
            curves: n,
            params: params.len(),
        });
    }
    if params.iter().any(|t| !t.is_finite()) {
        return Err(NurbsError::NonFinite("parameter"));
    }
    if let Some(i) = params.windows(2).position(|w| !(w[1] > w[0])) {
        return Err(NurbsError::BadParameters(i + 1));
    }
    Ok(())
}

/// Natural cubic interpolation of homogeneous points at strictly
/// increasing parameters: knots at the parameters (ends clamped), zero
/// second derivative at both ends. `K >= 2` points give `K + 2` control
/// points; two points give the straight segment.
pub fn interpolate_natural_cubic_h(
    points: &[DVec4],
    params: &[f64],
) -> Result<NurbsCurve, NurbsError> {
    let k = points.len();
    if k < 2 {
        return Err(NurbsError::TooFewPoints { got: k, need: 2 });
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(NurbsError::NonFinite("data point"));
    }
    check_params(params, k)?;
    let knots = natural_knots(params);
    let basis = natural_matrix(params, &knots);
    let mut rhs = Vec::with_capacity(k + 2);
    rhs.push(DVec4::ZERO);
    rhs.extend_from_slice(points);
    rhs.push(DVec4::ZERO);
    let ctrl = solve(basis, rhs)?;
    NurbsCurve::new(3, knots, ctrl)
}

/// [`interpolate_natural_cubic_h`] for Euclidean points (weights 1).
pub fn interpolate_natural_cubic(
    points: &[DVec3],
    params: &[f64],
) -> Result<NurbsCurve, NurbsError> {
    let h: Vec<DVec4> = points.iter().map(|p| homogeneous(*p, 1.0)).collect();
    let mut c = interpolate_natural_cubic_h(&h, params)?;
    for cp in &mut c.control {
        cp.w = 1.0;
    }
    Ok(c)
}

pub(crate) fn natural_knots(params: &[f64]) -> Vec<f64> {
    let k = params.len();
    let mut knots = vec![params[0]; 4];
    knots.extend_from_slice(&params[1..k - 1]);
    knots.extend(std::iter::repeat_n(params[k - 1], 4));
    knots
}

/// The `(K+2) x (K+2)` system of the natural cubic interpolant: row 0 and
/// row K+1 are the end second derivatives, rows 1..=K the interpolation.
pub(crate) fn natural_matrix(params: &[f64], knots: &[f64]) -> Vec<f64> {
    let k = params.len();
    let n = k + 2;
    let mut a = vec![0.0; n * n];
    for (r, &t) in params.iter().enumerate() {
        let span = find_span(n, 3, t, knots);
        let b = basis_funs(span, t, 3, knots);
        for (j, bj) in b.iter().enumerate() {
            a[(r + 1) * n + span - 3 + j] = *bj;
        }
    }
    for (row, t) in [(0usize, params[0]), (n - 1, params[k - 1])] {
        let span = find_span(n, 3, t, knots);
        let d = ders_basis_funs(span, t, 3, 2, knots);
        for j in 0..4 {
            a[row * n + span - 3 + j] = d[2][j];
        }
    }
    a
}

/// Closed interpolation (periodic cubic): the C2 closed curve through
/// `points` (the first point is not repeated at the end), returned in
/// clamped form on `[0, 1]` with `C(0) = C(1) = points[0]`.
pub fn interpolate_closed(points: &[DVec3], method: ParamMethod) -> Result<NurbsCurve, NurbsError> {
    check_points(points, 3)?;
    let n = points.len();
    let p = 3usize;
    let t = parameters(points, method, true)?; // n + 1 values, t[n] = 1
                                               // Periodic knot vector: U[i] = t_{i-p} extended with period 1.
    let ext = |i: isize| -> f64 {
        let ni = n as isize;
        let q = i.div_euclid(ni);
        let r = i.rem_euclid(ni) as usize;
        t[r] + q as f64
    };
    let knots: Vec<f64> = (0..(n + 2 * p + 1))
        .map(|i| ext(i as isize - p as isize))
        .collect();
    let n_ctrl = n + p;
    let mut a = vec![0.0; n * n];
    for (r, &ti) in t.iter().take(n).enumerate() {
        let span = find_span(n_ctrl, p, ti, &knots);
        let b = basis_funs(span, ti, p, &knots);
        for (j, bj) in b.iter().enumerate() {
            a[r * n + (span - p + j) % n] += *bj;
        }
    }
    let ctrl = solve(a, points.to_vec())?;
    let control: Vec<DVec4> = (0..n_ctrl).map(|i| homogeneous(ctrl[i % n], 1.0)).collect();
    let periodic = NurbsCurve::new(p, knots, control)?;
    let mut c = periodic.clamped();
    for cp in &mut c.control {
        cp.w = 1.0;
    }
    Ok(c)
}

/// Least-squares approximation (§9.4.1) with `n_ctrl` control points of
/// degree `degree`: end points interpolated, the rest fitted in the least
/// squares sense at the given parameters, knots by eq. 9.68-9.69.
pub fn approximate(
    points: &[DVec3],
    params: &[f64],
    degree: usize,
    n_ctrl: usize,
) -> Result<NurbsCurve, NurbsError> {
    check_points(points, 2)?;
    check_params(params, points.len())?;
    let m = points.len() - 1;
    if n_ctrl >= points.len() {
        return interpolate_at(points, params, degree);
    }
    let p = degree.min(n_ctrl - 1).max(1);
    let n = n_ctrl - 1;
    // Knots (eq. 9.68-9.69).
    let d = (m + 1) as f64 / (n - p + 1) as f64;
    let mut knots = vec![params[0]; p + 1];
    for j in 1..=(n - p) {
        let jd = j as f64 * d;
        let i = jd.floor() as usize;
        let alpha = jd - i as f64;
        knots.push((1.0 - alpha) * params[i - 1] + alpha * params[i]);
    }
    knots.extend(std::iter::repeat_n(params[m], p + 1));
    let mut ctrl = vec![points[0]; n + 1];
    ctrl[n] = points[m];
    if n >= 2 {
        let unknown = n - 1;
        let mut nt_n = vec![0.0; unknown * unknown];
        let mut nt_r = vec![DVec3::ZERO; unknown];
        for k in 1..m {
            let t = params[k];
            let span = find_span(n + 1, p, t, &knots);
            let b = basis_funs(span, t, p, &knots);
            let mut row = vec![0.0; n + 1];
            for (j, bj) in b.iter().enumerate() {
                row[span - p + j] = *bj;
            }
            let rk = points[k] - points[0] * row[0] - points[m] * row[n];
            for i in 1..n {
                if row[i] == 0.0 {
                    continue;
                }
                nt_r[i - 1] += rk * row[i];
                for j in 1..n {
                    nt_n[(i - 1) * unknown + j - 1] += row[i] * row[j];
                }
            }
        }
        let inner = solve(nt_n, nt_r)?;
        ctrl[1..n].copy_from_slice(&inner);
    }
    NurbsCurve::from_points(p, knots, &ctrl)
}

/// The least-squares approximation with the fewest control points (from
/// `degree + 1` up, doubling then bisecting) whose distance to every data
/// point at its parameter is at most `tol`; at worst the interpolant.
pub fn approximate_to_tolerance(
    points: &[DVec3],
    degree: usize,
    tol: f64,
    method: ParamMethod,
) -> Result<NurbsCurve, NurbsError> {
    check_points(points, 2)?;
    if !tol.is_finite() || tol <= 0.0 {
        return Err(NurbsError::NonFinite(
            "tolerance must be positive and finite",
        ));
    }
    let params = parameters(points, method, false)?;
    let max_err = |c: &NurbsCurve| -> f64 {
        points
            .iter()
            .zip(&params)
            .map(|(q, t)| (c.point(*t) - *q).length())
            .fold(0.0, f64::max)
    };
    let total = points.len();
    let lo_start = (degree + 1).min(total);
    let fit = |n: usize| approximate(points, &params, degree, n);
    let mut lo = lo_start;
    let first = fit(lo)?;
    if max_err(&first) <= tol {
        return Ok(first);
    }
    // Exponential search for a passing count, then bisection.
    let mut hi = lo;
    let mut best;
    loop {
        hi = (hi * 2).min(total);
        let c = fit(hi)?;
        if max_err(&c) <= tol || hi == total {
            best = c;
            break;
        }
        lo = hi;
    }
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        let c = fit(mid)?;
        if max_err(&c) <= tol {
            hi = mid;
            best = c;
        } else {
            lo = mid;
        }
    }
    Ok(best)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::fm::DetMath as _;

    fn wavy(n: usize) -> Vec<DVec3> {
        (0..n)
            .map(|i| {
                let t = i as f64 / (n - 1) as f64;
                DVec3::new(t * 4.0, (t * 6.0).fsin(), 0.3 * (t * 3.0).fcos())
            })
            .collect()
    }

    #[test]
    fn global_interpolation_passes_through_points() {
        let pts = wavy(9);
        for m in [ParamMethod::ChordLength, ParamMethod::Centripetal] {
            let c = interpolate(&pts, 3, m).unwrap();
            let t = parameters(&pts, m, false).unwrap();
            for (q, ti) in pts.iter().zip(&t) {
                assert!((c.point(*ti) - *q).length() < 1e-12);
            }
        }
    }

    #[test]
    fn closed_interpolation_is_closed_and_smooth() {
        let pts: Vec<DVec3> = (0..7)
            .map(|i| {
                let a = i as f64 / 7.0 * std::f64::consts::TAU;
                DVec3::new(a.fcos() * (1.0 + 0.2 * (3.0 * a).fsin()), a.fsin(), 0.0)
            })
            .collect();
        let c = interpolate_closed(&pts, ParamMethod::ChordLength).unwrap();
        assert!(c.is_clamped());
        let t = parameters(&pts, ParamMethod::ChordLength, true).unwrap();
        for (q, ti) in pts.iter().zip(&t) {
            assert!((c.point(*ti) - *q).length() < 1e-12);
        }
        assert!((c.point(1.0) - pts[0]).length() < 1e-12);
        let d0 = c.derivatives(0.0, 2);
        let d1 = c.derivatives(1.0, 2);
        assert!((d0[1] - d1[1]).length() < 1e-9);
        assert!((d0[2] - d1[2]).length() < 1e-7);
    }

    #[test]
    fn natural_cubic_insert_invariance() {
        let pts = wavy(5);
        let t = [0.0, 0.2, 0.45, 0.7, 1.0];
        let c = interpolate_natural_cubic(&pts, &t).unwrap();
        let extra = c.point(0.33);
        let mut p2 = pts.clone();
        p2.insert(2, extra);
        let t2 = [0.0, 0.2, 0.33, 0.45, 0.7, 1.0];
        let c2 = interpolate_natural_cubic(&p2, &t2).unwrap();
        for i in 0..=200 {
            let u = i as f64 / 200.0;
            assert!((c.point(u) - c2.point(u)).length() < 1e-12);
        }
        assert!(c.derivatives(0.0, 2)[2].length() < 1e-9);
    }

    #[test]
    fn approximation_meets_tolerance_with_fewer_points() {
        let pts = wavy(60);
        let c = approximate_to_tolerance(&pts, 3, 1e-3, ParamMethod::ChordLength).unwrap();
        assert!(c.control.len() < 60);
        let t = parameters(&pts, ParamMethod::ChordLength, false).unwrap();
        for (q, ti) in pts.iter().zip(&t) {
            assert!((c.point(*ti) - *q).length() <= 1e-3);
        }
    }
}
