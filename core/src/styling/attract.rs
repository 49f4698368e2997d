//! Attractor tools (paper §2.2 eq. 5 and §3.3, after Welch/Witkin and
//! Wesselink [39, 40]): a curve, or the part of it around the pointer, is
//! drawn towards a point, a line, a plane or another curve of the network.
//!
//! Each frame minimizes
//!
//! ```text
//! E = w_e ∫ g(s) |M (x(t) - y(t))|² dt + w_p0 ∫ |x - r|² dt + w_p1 ∫ |x' - r'|² dt
//! ```
//!
//! with `r` the curve at the start of the frame (shape preservation, eq.
//! 13-15), `g` the gaussian of eq. 19 around the pointed parameter (or 1
//! with `alpha = 0`), and `M (x - y)` the attractor's residual: `x - p` for
//! a point, the component normal to a line or the normal component for a
//! plane (`M` its projector), `x - y` for a curve. Locality is as for the
//! smoother (see [`super::tools`]): control points whose support leaves the
//! gaussian's support are fixed. The matrix is the same in every frame, so
//! it is factored once per application and each frame is one solve.
//!
//! A frame moves every point a fixed fraction of the way: where the
//! attractor's target is itself a spline of the curve's knots (a point,
//! the projection onto a line or a plane, the nearest points of a straight
//! curve) and the weights are uniform with free ends and `w_p1 = 0`, the
//! exact minimizer is `x = r + c M (y - r)` with `c = w_e / (w_e + w_p0)`,
//! so distances to the attractor shrink by `1 - c` per frame (the tests
//! check this to rounding).
//!
//! The curve attractor of \[40\] maps parameters linearly between the two
//! curves; we take each quadrature point's nearest point on the other
//! curve instead (recomputed every frame), so that a local attraction pulls
//! towards the nearest part of the other curve, whatever the two curves'
//! parameterizations.

use serde::{Deserialize, Serialize};

use crate::math::{DMat3, DVec3};

use super::curve::SplineCurve;
use super::edits::CurveId;
use super::energy::Weight;
use super::network::CurveNetwork;
use super::tools::{fixed_outside, CurveSession};
use super::StylingError;

/// What a curve is attracted to.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Attractor {
    /// A point `p`.
    Point {
        /// The point (model units).
        #[schemars(extend("x-unit" = "m"))]
        p: [f64; 3],
    },
    /// The line through `a` along `dir` (non-zero).
    Line {
        /// A point of the line.
        #[schemars(extend("x-unit" = "m"))]
        a: [f64; 3],
        /// Its direction (any length > 0).
        dir: [f64; 3],
    },
    /// The plane through `a` with normal `normal` (non-zero).
    Plane {
        /// A point of the plane.
        #[schemars(extend("x-unit" = "m"))]
        a: [f64; 3],
        /// Its normal (any length > 0).
        normal: [f64; 3],
    },
    /// Another curve of the same network (its nearest points).
    Curve {
        /// The attracting curve (another curve of the network).
        curve: CurveId,
    },
}

/// Weights of an attractor application.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AttractParams {
    /// Attractor weight `w_e` (eq. 5), in `(0, 1e6]`.
    #[schemars(extend("exclusiveMinimum" = 0.0), range(max = 1e6))]
    pub weight: f64,
    /// Position shape preservation `w_p0` (eq. 13), in `(0, 1e6]`.
    #[schemars(extend("exclusiveMinimum" = 0.0), range(max = 1e6))]
    pub wp0: f64,
    /// Tangent shape preservation `w_p1` (eq. 14), in `[0, 1e6]`.
    #[schemars(range(min = 0.0, max = 1e6))]
    pub wp1: f64,
    /// Sharpness of the gaussian around the pointed parameter (eq. 19,
    /// over the normalized parameter), in `[0, 1e4]`; 0 attracts the whole
    /// curve.
    #[schemars(range(min = 0.0, max = 1e4))]
    pub alpha: f64,
    /// Keep the curve's end points where they are.
    pub keep_ends: bool,
}

impl AttractParams {
    /// Checks the weights.
    pub fn validate(&self) -> Result<(), StylingError> {
        let ok = |v: f64, lo_open: bool, hi: f64| {
            v.is_finite() && v <= hi && if lo_open { v > 0.0 } else { v >= 0.0 }
        };
        if !ok(self.weight, true, 1e6) {
            return Err(StylingError::BadParameter(
                "attractor weight must be in (0, 1e6]",
            ));
        }
        if !ok(self.wp0, true, 1e6) {
            return Err(StylingError::BadParameter(
                "attractor wp0 must be in (0, 1e6]",
            ));
        }
        if !ok(self.wp1, false, 1e6) {
            return Err(StylingError::BadParameter(
                "attractor wp1 must be in [0, 1e6]",
            ));
        }
        if !ok(self.alpha, false, 1e4) {
            return Err(StylingError::BadParameter(
                "attractor alpha must be in [0, 1e4]",
            ));
        }
        Ok(())
    }

    /// The fraction of the way to the attractor one uniform frame moves
    /// (see the module doc).
    pub fn step_fraction(&self) -> f64 {
        self.weight / (self.weight + self.wp0)
    }
}

/// An attractor with its geometry resolved.
#[derive(Clone, Copy, Debug)]
pub enum Target<'a> {
    /// A point.
    Point(DVec3),
    /// A line: a point and a unit direction.
    Line(DVec3, DVec3),
    /// A plane: a point and a unit normal.
    Plane(DVec3, DVec3),
    /// A curve.
    Curve(&'a SplineCurve),
}

fn unit(v: [f64; 3], what: &'static str) -> Result<DVec3, StylingError> {
    let v = DVec3::from_array(v);
    let l = v.length();
    if !(l.is_finite() && l > 1e-12) {
        return Err(StylingError::BadParameter(what));
    }
    Ok(v / l)
}

fn finite(v: [f64; 3], what: &'static str) -> Result<DVec3, StylingError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(DVec3::from_array(v))
    } else {
        Err(StylingError::NonFinite(what))
    }
}

impl Target<'_> {
    /// The attractor's projector `M` and its target for a curve point `x`.
    fn residual(&self, x: DVec3, nearest: &dyn Fn(DVec3) -> DVec3) -> (DMat3, DVec3) {
        match *self {
            Self::Point(p) => (DMat3::IDENTITY, p),
            Self::Line(a, d) => (DMat3::IDENTITY - outer(d, d), a),
            Self::Plane(a, n) => (outer(n, n), a),
            Self::Curve(_) => (DMat3::IDENTITY, nearest(x)),
        }
    }

    /// Distance of `x` to the attractor.
    pub fn distance(&self, x: DVec3) -> f64 {
        match *self {
            Self::Point(p) => x.distance(p),
            Self::Line(a, d) => {
                let v = x - a;
                (v - d * v.dot(d)).length()
            }
            Self::Plane(a, n) => (x - a).dot(n).abs(),
            Self::Curve(c) => c.closest(x).1,
        }
    }
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Nearest points on a curve, from a dense sampling refined by Newton.
struct Nearest<'a> {
    curve: &'a SplineCurve,
    samples: Vec<(f64, DVec3)>,
}

impl<'a> Nearest<'a> {
    fn new(curve: &'a SplineCurve) -> Self {
        let (a, b) = curve.domain();
        let m = 8 * curve.n();
        let samples = (0..=m)
            .map(|i| {
                let t = a + (b - a) * i as f64 / m as f64;
                (t, curve.point(t))
            })
            .collect();
        Self { curve, samples }
    }

    fn at(&self, x: DVec3) -> DVec3 {
        let mut t = self.samples[0].0;
        let mut best = f64::INFINITY;
        for (ti, p) in &self.samples {
            let d = p.distance_squared(x);
            if d < best {
                best = d;
                t = *ti;
            }
        }
        for _ in 0..8 {
            let d = self.curve.derivs(t, 2);
            let f = (d[0] - x).dot(d[1]);
            let df = d[1].length_squared() + (d[0] - x).dot(d[2]);
            if !(df > 1e-300) {
                break;
            }
            t = self.curve.clamp(t - f / df);
        }
        self.curve.point(t)
    }
}

impl CurveSession {
    /// `frames` attractor frames (see the module doc) around the curve
    /// parameter `t0` (ignored with `alpha = 0`).
    pub fn attract(
        &mut self,
        p: &AttractParams,
        target: &Target,
        t0: f64,
        frames: usize,
    ) -> Result<(), StylingError> {
        p.validate()?;
        if frames == 0 || frames > super::tools::MAX_FRAMES {
            return Err(StylingError::BadParameter("frames must be 1..=100000"));
        }
        let b = super::budget::Budget::default();
        b.check_curve_tool("frames", frames, 3 * self.curve.n())?;
        let (a, bb) = self.curve.domain();
        let n = self.curve.n();
        let (weight, mut fixed) = if p.alpha > 0.0 {
            let w = Weight::gaussian((t0 - a) / (bb - a), p.alpha);
            let (sa, sb) = w.support();
            (
                w,
                fixed_outside(&self.curve, a + sa * (bb - a), a + sb * (bb - a)),
            )
        } else {
            (Weight::Uniform, vec![false; 3 * n])
        };
        if p.keep_ends {
            fixed[..3].fill(true);
            fixed[3 * n - 3..].fill(true);
        }
        if fixed.iter().all(|f| *f) {
            return Err(StylingError::BadParameter(
                "the attractor's region holds no free control point (alpha too large for this curve)",
            ));
        }
        let nearest = match target {
            Target::Curve(c) => Some(Nearest::new(c)),
            _ => None,
        };
        let near = |x: DVec3| nearest.as_ref().map_or(x, |nr| nr.at(x));
        for _ in 0..frames {
            let reference = self.curve.clone();
            let mut sys = self.system();
            match *target {
                Target::Curve(_) => {
                    // The target at each quadrature point: the nearest
                    // point of the attracting curve to the reference.
                    let f = |t: f64| near(reference.point(t));
                    sys.add_integral(0, weight, DMat3::IDENTITY, p.weight, Some(&f));
                }
                _ => {
                    let (m, y) = target.residual(DVec3::ZERO, &near);
                    let f = move |_t: f64| y;
                    sys.add_integral(0, weight, m, p.weight, Some(&f));
                }
            }
            sys.add_shape(0, p.wp0, &reference);
            if p.wp1 > 0.0 {
                sys.add_shape(1, p.wp1, &reference);
            }
            self.curve.ctrl = self.solve(&sys, &fixed)?;
        }
        Ok(())
    }
}

impl CurveNetwork {
    /// Attracts curve `curve` to `attractor` for `frames` frames, around
    /// the curve point nearest `at` (or everywhere with `alpha = 0`); the
    /// network's other curves follow at their junctions. On error the
    /// network is unchanged.
    pub fn attract(
        &mut self,
        curve: usize,
        p: &AttractParams,
        attractor: &Attractor,
        at: Option<[f64; 3]>,
        frames: usize,
    ) -> Result<(), StylingError> {
        p.validate()?;
        let c = self.curve(curve)?.clone();
        let other;
        let target = match *attractor {
            Attractor::Point { p } => Target::Point(finite(p, "attractor point")?),
            Attractor::Line { a, dir } => Target::Line(
                finite(a, "attractor line point")?,
                unit(dir, "attractor line direction must be non-zero")?,
            ),
            Attractor::Plane { a, normal } => Target::Plane(
                finite(a, "attractor plane point")?,
                unit(normal, "attractor plane normal must be non-zero")?,
            ),
            Attractor::Curve { curve: CurveId(o) } => {
                if o == curve {
                    return Err(StylingError::BadParameter(
                        "a curve cannot attract itself: pick another curve",
                    ));
                }
                other = self.curve(o)?.clone();
                Target::Curve(&other)
            }
        };
        let t0 = match at {
            Some(q) if p.alpha > 0.0 => c.closest(finite(q, "attractor pointer")?).0,
            None if p.alpha > 0.0 => {
                return Err(StylingError::BadParameter(
                    "a local attractor (alpha > 0) needs the pointer position `at`",
                ))
            }
            _ => c.domain().0,
        };
        let mut s = CurveSession::new(c)?;
        s.attract(p, &target, t0, frames)?;
        self.set_curve(curve, s.curve)
    }
}
