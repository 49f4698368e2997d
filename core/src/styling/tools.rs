//! Curve tools (paper §3): smoother, sharpener, puller.
//!
//! A tool session holds one [`FixedSolver`] for the curve's pattern (the
//! symbolic factorization is done once per activation). Each frame builds
//! the energy; the numeric factorization is redone only when the matrix
//! values changed (the pointed parameter moved), otherwise only the solve
//! runs. The minimization region is the support of the truncated gaussian
//! (§2.2: `[t0, t1]` with the first and last control points influencing it
//! fixed): control points whose basis support is not inside it are fixed by
//! the constraints, so the curve outside the support is exactly unchanged.
//! The end control points are always fixed (eq. 7).
//!
//! Where the gaussian goes: the paper weights the bend and stretch terms
//! by the gaussian `w(t)` (eq. 17-19). We weight the shape-preserving term
//! by `1 / w(t)` instead, with bend and stretch uniform over the region:
//! the locality is the same (the curve changes most at `t0` and not at all
//! outside the support), and it makes the frame provably monotone. The
//! reference `r` is feasible, so `E(new) <= E(r) = w_b E_b(r)` and, the
//! shape term being >= 0, the bend energy over the region (and so of the
//! whole curve) cannot rise under the smoother; with negated weights the
//! sharpener's cannot fall (as long as the matrix stays positive definite,
//! which the safety limits watch). With the bend weighted by the gaussian
//! itself, curvature drifts to the low-weight flanks and the total bend
//! energy was seen to rise.

use serde::{Deserialize, Serialize};

use crate::math::DVec3;

use super::budget::Budget;
use super::curve::{SplineCurve, DEGREE};
use super::energy::{curve_pattern, flatten, unflatten, CurveSystem, Weight};
use super::solver::FixedSolver;
use super::StylingError;

/// Weights of the smoother and sharpener (eq. 18-19), relative to the curve
/// parameter normalized to `[0, 1]` (energies are integrals over the
/// curve's own parameter; see [`CurveSystem`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SmoothParams {
    /// Bend weight `w_b` (the sharpener uses `-w_b`). Must be > 0.
    pub wb: f64,
    /// Stretch weight `w_s` (the sharpener uses `-w_s`). Must be >= 0.
    pub ws: f64,
    /// Position shape-preservation weight `w_p0` (eq. 13). Must be > 0.
    pub wp0: f64,
    /// Tangent shape-preservation weight `w_p1` (eq. 14). Must be >= 0.
    pub wp1: f64,
    /// Curvature shape-preservation weight `w_p2` (`∫ |x'' - r''|²`). The
    /// sharpener needs `w_p2 > w_b`: the quadratic part is then
    /// `(w_p2 - w_b) E_b + ...`, positive definite, and each frame
    /// amplifies curvature by at most `w_p2 / (w_p2 - w_b)`. Must be >= 0.
    pub wp2: f64,
    /// Gaussian sharpness `a` of eq. 19 over the normalized parameter.
    pub alpha: f64,
}

/// Limits that make the sharpener stop safely.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SharpenLimits {
    /// Largest control-point move in one frame (model units).
    pub max_step: f64,
    /// Largest bend energy, as a multiple of the energy at activation.
    pub max_growth: f64,
}

/// Weights of the puller (eq. 21).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PullParams {
    /// Point-to-point attractor weight `w_pp`. Must be > 0.
    pub wpp: f64,
    /// Position shape preservation `w_p0`. Must be > 0.
    pub wp0: f64,
    /// Tangent shape preservation `w_p1`. Must be >= 0.
    pub wp1: f64,
}

/// Why a sharpener stopped before the end of its path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// A frame would have moved a control point more than `max_step`.
    StepTooLarge,
    /// A frame would have raised the bend energy past `max_growth`.
    EnergyGrowth,
    /// The energy matrix became singular or the solve non-finite.
    Unstable,
}

/// The maximum frames one held tool application may carry.
pub const MAX_FRAMES: usize = 100_000;

fn check_pos(name: &'static str, v: f64) -> Result<(), StylingError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(StylingError::BadParameter(name))
    }
}

fn check_nonneg(name: &'static str, v: f64) -> Result<(), StylingError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(StylingError::BadParameter(name))
    }
}

impl SmoothParams {
    /// Checks every weight.
    pub fn validate(&self) -> Result<(), StylingError> {
        check_pos("wb must be > 0", self.wb)?;
        check_nonneg("ws must be >= 0", self.ws)?;
        check_pos("wp0 must be > 0", self.wp0)?;
        check_nonneg("wp1 must be >= 0", self.wp1)?;
        check_nonneg("wp2 must be >= 0", self.wp2)?;
        check_pos("alpha must be > 0", self.alpha)
    }
}

impl PullParams {
    /// Checks every weight.
    pub fn validate(&self) -> Result<(), StylingError> {
        check_pos("wpp must be > 0", self.wpp)?;
        check_pos("wp0 must be > 0", self.wp0)?;
        check_nonneg("wp1 must be >= 0", self.wp1)
    }
}

impl SharpenLimits {
    /// Checks the limits.
    pub fn validate(&self) -> Result<(), StylingError> {
        check_pos("max_step must be > 0", self.max_step)?;
        if !(self.max_growth.is_finite() && self.max_growth > 1.0) {
            return Err(StylingError::BadParameter("max_growth must be > 1"));
        }
        Ok(())
    }
}

/// Checks a pointer path: non-empty, finite, at most [`MAX_FRAMES`].
pub fn check_path(path: &[[f64; 3]]) -> Result<Vec<DVec3>, StylingError> {
    if path.is_empty() || path.len() > MAX_FRAMES {
        return Err(StylingError::BadParameter(
            "pointer path must have 1..=100000 samples",
        ));
    }
    if let Some(i) = path.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
        return Err(StylingError::NonFiniteSample(i));
    }
    Ok(path.iter().map(|p| DVec3::from_array(*p)).collect())
}

/// Unknowns fixed for a minimization region `[ta, tb]` (curve parameter):
/// every control point whose basis support is not inside it, and the ends.
pub fn fixed_outside(curve: &SplineCurve, ta: f64, tb: f64) -> Vec<bool> {
    let n = curve.n();
    let mut fixed = vec![false; 3 * n];
    for i in 0..n {
        let (lo, hi) = (curve.knots[i], curve.knots[i + DEGREE + 1]);
        let inside = lo >= ta && hi <= tb;
        if !inside || i == 0 || i == n - 1 {
            fixed[3 * i..3 * i + 3].fill(true);
        }
    }
    fixed
}

/// A curve tool held over several frames, reusing its factorization.
#[derive(Debug)]
pub struct CurveSession {
    /// The curve as edited so far.
    pub curve: SplineCurve,
    solver: FixedSolver,
}

impl CurveSession {
    /// Activates a tool on `curve` (symbolic factorization).
    pub fn new(curve: SplineCurve) -> Result<Self, StylingError> {
        let solver = FixedSolver::new(curve_pattern(curve.n()))?;
        Ok(Self { curve, solver })
    }

    /// Refuses a pointer path whose frames would exceed the default
    /// budget's tool work or time, or that reaches outside its extent.
    pub fn check_work(&self, path: &[DVec3]) -> Result<(), StylingError> {
        let b = Budget::default();
        b.check_extent("path", path)?;
        b.check_curve_tool("path", path.len(), 3 * self.curve.n())
    }

    /// Numeric factorizations done so far.
    pub fn refactor_count(&self) -> usize {
        self.solver.refactor_count
    }

    pub(crate) fn system(&self) -> CurveSystem {
        CurveSystem::new(&self.curve, self.solver.pattern().clone())
    }

    pub(crate) fn solve(
        &mut self,
        sys: &CurveSystem,
        fixed: &[bool],
    ) -> Result<Vec<[f64; 3]>, StylingError> {
        self.solver.factor(&sys.values, fixed)?;
        let x = self.solver.solve(&sys.rhs, &flatten(&self.curve.ctrl), 1)?;
        Ok(unflatten(&x))
    }

    /// One smoother (`sign = 1`) or sharpener (`sign = -1`) frame at the
    /// curve parameter `t0`: the reference is the current curve. Returns
    /// the new control points without applying them.
    pub fn smooth_step(
        &mut self,
        p: &SmoothParams,
        t0: f64,
        sign: f64,
    ) -> Result<Vec<[f64; 3]>, StylingError> {
        let (a, b) = self.curve.domain();
        let s0 = (t0 - a) / (b - a);
        let weight = Weight::gaussian(s0, p.alpha);
        let (sa, sb) = weight.support();
        let fixed = fixed_outside(&self.curve, a + sa * (b - a), a + sb * (b - a));
        let reference = self.curve.clone();
        let mut sys = self.system();
        sys.add_bend(sign * p.wb, Weight::Uniform);
        if p.ws > 0.0 {
            sys.add_stretch(sign * p.ws, Weight::Uniform);
        }
        let hold = weight.inverse();
        sys.add_shape_weighted(0, p.wp0, hold, &reference);
        if p.wp1 > 0.0 {
            sys.add_shape_weighted(1, p.wp1, hold, &reference);
        }
        if p.wp2 > 0.0 {
            sys.add_shape_weighted(2, p.wp2, hold, &reference);
        }
        self.solve(&sys, &fixed)
    }

    /// Smoother over a pointer path (one frame per sample, §3.1).
    pub fn smooth(&mut self, p: &SmoothParams, path: &[DVec3]) -> Result<(), StylingError> {
        self.check_work(path)?;
        for q in path {
            let (t0, _) = self.curve.closest(*q);
            self.curve.ctrl = self.smooth_step(p, t0, 1.0)?;
        }
        Ok(())
    }

    /// Sharpener over a pointer path (§3.2): negative weights, stopping
    /// before a frame that moves too far, grows the bend energy past the
    /// limit, or fails. Returns the frames applied and why it stopped; a
    /// path over the budget is an error before any frame runs.
    pub fn sharpen(
        &mut self,
        p: &SmoothParams,
        limits: &SharpenLimits,
        path: &[DVec3],
    ) -> Result<(usize, Option<StopReason>), StylingError> {
        self.check_work(path)?;
        Ok(self.sharpen_frames(p, limits, path))
    }

    fn sharpen_frames(
        &mut self,
        p: &SmoothParams,
        limits: &SharpenLimits,
        path: &[DVec3],
    ) -> (usize, Option<StopReason>) {
        let e0 = self.curve.bend_energy();
        for (k, q) in path.iter().enumerate() {
            let (t0, _) = self.curve.closest(*q);
            let next = match self.smooth_step(p, t0, -1.0) {
                Ok(c) => c,
                Err(_) => return (k, Some(StopReason::Unstable)),
            };
            let step = next
                .iter()
                .zip(&self.curve.ctrl)
                .map(|(a, b)| DVec3::from_array(*a).distance(DVec3::from_array(*b)))
                .fold(0.0, f64::max);
            if !step.is_finite() {
                return (k, Some(StopReason::Unstable));
            }
            if step > limits.max_step {
                return (k, Some(StopReason::StepTooLarge));
            }
            let candidate = SplineCurve {
                knots: self.curve.knots.clone(),
                ctrl: next,
            };
            let e = candidate.bend_energy();
            if !e.is_finite() {
                return (k, Some(StopReason::Unstable));
            }
            if e > limits.max_growth * e0 {
                return (k, Some(StopReason::EnergyGrowth));
            }
            self.curve = candidate;
        }
        (path.len(), None)
    }

    /// Puller (§3.3): the curve point at `t0` is attracted to each path
    /// sample in turn; the reference is the curve at activation, and the
    /// matrix is the same every frame (one numeric factorization).
    pub fn pull(&mut self, p: &PullParams, t0: f64, path: &[DVec3]) -> Result<(), StylingError> {
        self.check_work(path)?;
        let reference = self.curve.clone();
        let n = self.curve.n();
        let mut fixed = vec![false; 3 * n];
        fixed[..3].fill(true);
        fixed[3 * n - 3..].fill(true);
        for q in path {
            let mut sys = self.system();
            sys.add_point_to_point(p.wpp, t0, *q);
            sys.add_shape(0, p.wp0, &reference);
            if p.wp1 > 0.0 {
                sys.add_shape(1, p.wp1, &reference);
            }
            self.curve.ctrl = self.solve(&sys, &fixed)?;
        }
        Ok(())
    }
}
