//! Cubic B-spline curves drawn in space (paper §2.2, §5.1).
//!
//! A [`SplineCurve`] is a clamped, non-rational cubic B-spline with its
//! knots and control points. It is built from tracked samples by
//! [`fit_curve`]: the samples are checked (at least 4, finite, no two
//! consecutive ones coincident), optionally resampled by arc length (noisy
//! tracker input bunches up where the hand slows down and jitters; equal
//! spacing removes that before fitting), then either interpolated
//! (chord-length parameters, `nurbs::interpolate`) or approximated to a
//! tolerance (`nurbs::approximate_to_tolerance`). Basis functions come from
//! `core::nurbs`. The number of points to fit is checked against a
//! [`Budget`] before resampling allocates them (issue 22: a far sample or a
//! tiny spacing once asked for terabytes).

use serde::{Deserialize, Serialize};

use crate::math::DVec3;
use crate::nurbs::{self, basis_funs, ders_basis_funs, find_span, ParamMethod};

use super::budget::Budget;
use super::StylingError;

/// A clamped cubic B-spline curve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SplineCurve {
    /// Knot vector, clamped (first and last knots repeated 4 times).
    pub knots: Vec<f64>,
    /// Control points.
    pub ctrl: Vec<[f64; 3]>,
}

/// How samples become a curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "mode", rename_all = "snake_case")]
pub enum FitMode {
    /// Interpolate every (resampled) sample.
    Interpolate,
    /// Fewest control points with every sample within `tol`.
    Approximate {
        /// Distance tolerance.
        tol: f64,
    },
}

/// Degree of every styling curve.
pub const DEGREE: usize = 3;

impl SplineCurve {
    /// A curve after checking the knots and control points.
    pub fn new(knots: Vec<f64>, ctrl: Vec<[f64; 3]>) -> Result<Self, StylingError> {
        if ctrl.len() < 4 || knots.len() != ctrl.len() + DEGREE + 1 {
            return Err(StylingError::BadCurve(
                "a cubic curve needs >= 4 control points and n + 4 knots".into(),
            ));
        }
        if knots.iter().any(|k| !k.is_finite()) || ctrl.iter().flatten().any(|v| !v.is_finite()) {
            return Err(StylingError::NonFinite("curve"));
        }
        if knots.windows(2).any(|w| w[1] < w[0]) || !(knots[knots.len() - 1] > knots[0]) {
            return Err(StylingError::BadCurve("knots must increase".into()));
        }
        Ok(Self { knots, ctrl })
    }

    /// Number of control points.
    pub fn n(&self) -> usize {
        self.ctrl.len()
    }

    /// Parameter domain.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[DEGREE], self.knots[self.ctrl.len()])
    }

    /// Clamps `t` into the domain.
    pub fn clamp(&self, t: f64) -> f64 {
        let (a, b) = self.domain();
        t.clamp(a, b)
    }

    /// The knot span of `t` and the 4 basis functions there.
    pub fn basis(&self, t: f64) -> (usize, Vec<f64>) {
        let t = self.clamp(t);
        let span = find_span(self.n(), DEGREE, t, &self.knots);
        (span - DEGREE, basis_funs(span, t, DEGREE, &self.knots))
    }

    /// Basis derivatives up to `d` at `t`: `(first index, ders[k][j])`.
    pub fn basis_ders(&self, t: f64, d: usize) -> (usize, Vec<Vec<f64>>) {
        let t = self.clamp(t);
        let span = find_span(self.n(), DEGREE, t, &self.knots);
        (
            span - DEGREE,
            ders_basis_funs(span, t, DEGREE, d, &self.knots),
        )
    }

    /// Point at `t`.
    pub fn point(&self, t: f64) -> DVec3 {
        let (first, b) = self.basis(t);
        b.iter()
            .enumerate()
            .map(|(j, w)| DVec3::from_array(self.ctrl[first + j]) * *w)
            .sum()
    }

    /// Derivatives `0..=d` at `t`.
    pub fn derivs(&self, t: f64, d: usize) -> Vec<DVec3> {
        let (first, ders) = self.basis_ders(t, d);
        ders.iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .map(|(j, w)| DVec3::from_array(self.ctrl[first + j]) * *w)
                    .sum()
            })
            .collect()
    }

    /// `count` points at uniform parameters over the domain.
    pub fn polyline(&self, count: usize) -> Vec<DVec3> {
        let (a, b) = self.domain();
        let count = count.max(2);
        (0..count)
            .map(|i| self.point(a + (b - a) * i as f64 / (count - 1) as f64))
            .collect()
    }

    /// The parameter of the point closest to `p` (dense sampling, then
    /// Newton steps on `(c(t) - p) · c'(t) = 0`), and the distance.
    pub fn closest(&self, p: DVec3) -> (f64, f64) {
        let (a, b) = self.domain();
        let samples = 8 * self.n();
        let mut best = (a, f64::INFINITY);
        for i in 0..=samples {
            let t = a + (b - a) * i as f64 / samples as f64;
            let d = self.point(t).distance(p);
            if d < best.1 {
                best = (t, d);
            }
        }
        let mut t = best.0;
        for _ in 0..20 {
            let d = self.derivs(t, 2);
            let f = (d[0] - p).dot(d[1]);
            let df = d[1].length_squared() + (d[0] - p).dot(d[2]);
            if !(df.abs() > 1e-300) {
                break;
            }
            let nt = self.clamp(t - f / df);
            if (nt - t).abs() < 1e-15 * (b - a) {
                t = nt;
                break;
            }
            t = nt;
        }
        let d = self.point(t).distance(p);
        if d < best.1 {
            (t, d)
        } else {
            best
        }
    }

    /// Bend energy `∫ |c''|²` by Gauss quadrature (exact for cubics).
    pub fn bend_energy(&self) -> f64 {
        self.integrate(|d| d[2].length_squared())
    }

    /// Stretch energy `∫ |c'|²`.
    pub fn stretch_energy(&self) -> f64 {
        self.integrate(|d| d[1].length_squared())
    }

    fn integrate(&self, f: impl Fn(&[DVec3]) -> f64) -> f64 {
        let mut sum = 0.0;
        for (t, w) in super::energy::quadrature_points(&self.knots) {
            sum += w * f(&self.derivs(t, 2));
        }
        sum
    }

    /// Points as `DVec3`.
    pub fn ctrl_points(&self) -> Vec<DVec3> {
        self.ctrl.iter().map(|p| DVec3::from_array(*p)).collect()
    }

    /// This curve as a `core::nurbs` curve.
    pub fn to_nurbs(&self) -> Result<nurbs::NurbsCurve, StylingError> {
        Ok(nurbs::NurbsCurve::from_points(
            DEGREE,
            self.knots.clone(),
            &self.ctrl_points(),
        )?)
    }

    /// A curve from a `core::nurbs` curve of degree 3 with unit weights.
    pub fn from_nurbs(c: &nurbs::NurbsCurve) -> Result<Self, StylingError> {
        if c.degree != DEGREE {
            return Err(StylingError::BadCurve("styling curves are cubic".into()));
        }
        Self::new(
            c.knots.clone(),
            c.control
                .iter()
                .map(|h| nurbs::euclidean(*h).to_array())
                .collect(),
        )
    }
}

/// Checks tracked samples: at least 4, all finite, no two consecutive
/// samples closer than `1e-9`.
pub fn check_samples(samples: &[[f64; 3]]) -> Result<Vec<DVec3>, StylingError> {
    if samples.len() < 4 {
        return Err(StylingError::TooFewSamples(samples.len()));
    }
    if let Some(i) = samples
        .iter()
        .position(|s| s.iter().any(|v| !v.is_finite()))
    {
        return Err(StylingError::NonFiniteSample(i));
    }
    let pts: Vec<DVec3> = samples.iter().map(|s| DVec3::from_array(*s)).collect();
    if let Some(i) = pts.windows(2).position(|w| w[0].distance(w[1]) < 1e-9) {
        return Err(StylingError::CoincidentSamples(i, i + 1));
    }
    Ok(pts)
}

/// The number of points [`resample`] makes of a polyline of length
/// `total` at spacing `h` (an `f64`, so that an absurd request is seen
/// before anything is allocated: infinite or NaN when `total / h` is).
pub fn resample_count(total: f64, h: f64) -> f64 {
    (total / h).round().max(3.0) + 1.0
}

/// Resamples a polyline at equal arc-length spacing `h` (at least 4
/// points; the end points are kept), refusing more than `max_points`
/// points with [`StylingError::OverBudget`] before allocating them.
pub fn resample(points: &[DVec3], h: f64, max_points: usize) -> Result<Vec<DVec3>, StylingError> {
    if points.len() < 2 {
        return Err(StylingError::TooFewSamples(points.len()));
    }
    let mut cum = vec![0.0];
    for w in points.windows(2) {
        let l = cum[cum.len() - 1] + w[0].distance(w[1]);
        cum.push(l);
    }
    let total = cum[cum.len() - 1];
    let estimate = resample_count(total, h);
    if !(estimate <= max_points as f64) {
        return Err(StylingError::OverBudget(crate::budget::OverBudget::new(
            "resample",
            "the number of points to fit (stroke length / spacing + 1)",
            estimate,
            max_points as f64,
        )));
    }
    // Exact: `estimate` is a whole number no larger than `max_points`.
    let count = estimate as usize;
    let mut out = Vec::with_capacity(count);
    let mut seg = 0;
    for i in 0..count {
        let s = total * i as f64 / (count - 1) as f64;
        while seg + 2 < cum.len() && cum[seg + 1] < s {
            seg += 1;
        }
        let len = cum[seg + 1] - cum[seg];
        let a = if len > 0.0 { (s - cum[seg]) / len } else { 0.0 };
        out.push(points[seg].lerp(points[seg + 1], a.clamp(0.0, 1.0)));
    }
    out[0] = points[0];
    out[count - 1] = points[points.len() - 1];
    Ok(out)
}

/// A cubic curve from tracked samples: checked, resampled at spacing
/// `resample_h` if given, then interpolated or approximated, within the
/// default [`Budget`].
pub fn fit_curve(
    samples: &[[f64; 3]],
    mode: FitMode,
    resample_h: Option<f64>,
) -> Result<SplineCurve, StylingError> {
    fit_curve_within(samples, mode, resample_h, &Budget::default())
}

/// [`fit_curve`] within `budget`: samples far from the origin, and more
/// points to fit than the budget allows (counted before resampling
/// allocates them), are typed errors.
pub fn fit_curve_within(
    samples: &[[f64; 3]],
    mode: FitMode,
    resample_h: Option<f64>,
    budget: &Budget,
) -> Result<SplineCurve, StylingError> {
    let pts = check_samples(samples)?;
    budget.check_extent("samples", &pts)?;
    let pts = match resample_h {
        Some(h) if h.is_finite() && h > 0.0 => resample(&pts, h, budget.max_fit_points)?,
        Some(_) => return Err(StylingError::BadParameter("resample spacing must be > 0")),
        None => {
            budget.check_fit_points("samples", pts.len() as f64)?;
            pts
        }
    };
    let c = match mode {
        FitMode::Interpolate => nurbs::interpolate(&pts, DEGREE, ParamMethod::ChordLength)?,
        FitMode::Approximate { tol } => {
            if !(tol > 0.0) || !tol.is_finite() {
                return Err(StylingError::BadParameter("tolerance must be > 0"));
            }
            let c = nurbs::approximate_to_tolerance(&pts, DEGREE, tol, ParamMethod::ChordLength)?;
            if c.control.len() < 4 {
                nurbs::interpolate(&pts, DEGREE, ParamMethod::ChordLength)?
            } else {
                c
            }
        }
    };
    SplineCurve::from_nurbs(&c)
}
