//! How many key sections a sketched spine needs, and where (paper 1 §3.1
//! eq. 2 and §3.3; issue 20 "sketches that keep their shape").
//!
//! A generalized cylinder's side surface is the skin through its placed
//! key sections, natural cubic in `v` with the sections' spine parameters
//! as `v`-parameters ([`crate::gc::Gc::surface`]). Between two sections
//! the surface therefore follows the natural cubic through the placed
//! sections, not the spine: two sections on a sketched arc give a straight
//! tube. [`section_params`] chooses the parameters so that the skin stays
//! within a tolerance of the tube the spine describes.
//!
//! Choices:
//! - **Measured, not guessed from curvature alone.** The skin is linear in
//!   the section control points, so its error is bounded by the error of
//!   natural cubic interpolation of five rails: the spine `A(v)` and
//!   `A(v) ± ρ r(v)`, `A(v) ± ρ s(v)` (the rotation-minimizing frame axes
//!   scaled by the sections' largest radius `ρ`). Starting from the two
//!   ends, every interval whose rails deviate by more than the tolerance
//!   (checked at [`CHECKS_PER_INTERVAL`] interior samples) is halved, until
//!   none does. Curvature decides the count through that error (cubic
//!   interpolation errs like `h^4` times the rail's fourth derivative, so
//!   tight bends get dense sections and straight runs none).
//! - **Bends tighter than the section fold the tube.** Where the spine's
//!   radius of curvature is below `ρ`, the inner side of the tube would
//!   pass through itself; [`section_params`] refuses with
//!   [`SketchError::TooTight`] naming where and how tight, instead of
//!   leaving the mesher to fail with a generic message.
//! - Values in, values out: the spine is a [`Spine`] (what `gc::fit_spine`
//!   makes from a stroke's simplified points), the result plain numbers.

use glam::DVec3;

use super::stroke::{length, resample};
use super::{fit_spine_stroke, project_stroke, SketchError, SketchPlane, SPINE_SAMPLES};
use crate::gc::{fit_spine, Spine, SpineFrames};
use crate::nurbs::interpolate_natural_cubic;

/// Interior samples per interval at which the skin's error is measured.
pub const CHECKS_PER_INTERVAL: usize = 8;

/// Samples along the spine at which its curvature is checked.
pub const CURVATURE_SAMPLES: usize = 512;

/// Settings of [`section_params`] and [`sketch_spine`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionSettings {
    /// Largest distance of the skin from the tube (model units).
    pub tolerance: f64,
    /// Most key sections a spine may get.
    pub max_sections: usize,
    /// RDP / fitting tolerance of the stroke (model units), see
    /// [`fit_spine_stroke`].
    pub stroke_tolerance: f64,
}

impl Default for SectionSettings {
    fn default() -> Self {
        Self {
            tolerance: 2.5e-4,
            max_sections: 64,
            stroke_tolerance: 5e-4,
        }
    }
}

/// The sections a spine needs: their parameters and how well the skin
/// then follows the tube.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionPlan {
    /// Spine parameters of the key sections, increasing, first and last
    /// at the spine's ends.
    pub params: Vec<f64>,
    /// Largest rail deviation found with these sections (model units).
    pub max_error: f64,
    /// Smallest radius of curvature of the spine (infinite when straight).
    pub min_bend_radius: f64,
}

fn frame_rails(
    spine: &Spine,
    frames: &SpineFrames,
    radius: f64,
    v: f64,
) -> Result<[DVec3; 5], SketchError> {
    let f = frames.at(spine, v)?;
    let a = spine.curve.point(v);
    Ok([
        a,
        a + f.r * radius,
        a - f.r * radius,
        a + f.s * radius,
        a - f.s * radius,
    ])
}

/// Smallest radius of curvature of the spine and the parameter where it
/// occurs (a zero tangent is [`SketchError::ZeroLength`]).
fn min_bend(spine: &Spine) -> Result<(f64, f64), SketchError> {
    let (a, b) = spine.curve.domain();
    let mut best = (f64::INFINITY, a);
    for i in 0..=CURVATURE_SAMPLES {
        let v = a + (b - a) * i as f64 / CURVATURE_SAMPLES as f64;
        let d = spine.curve.derivatives(v, 2);
        let speed = d[1].length();
        if !(speed > 0.0) {
            return Err(SketchError::ZeroLength);
        }
        let k = d[1].cross(d[2]).length() / (speed * speed * speed);
        let r = if k > 0.0 { 1.0 / k } else { f64::INFINITY };
        if r < best.0 {
            best = (r, v);
        }
    }
    Ok(best)
}

/// Key-section parameters for `spine` with sections reaching `radius` from
/// it: every interval is halved until the skin's rails stay within
/// `settings.tolerance` of the tube, at most `settings.max_sections`.
pub fn section_params(
    spine: &Spine,
    radius: f64,
    settings: &SectionSettings,
) -> Result<SectionPlan, SketchError> {
    for (what, value) in [("radius", radius), ("tolerance", settings.tolerance)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(SketchError::BadParameter { what, value });
        }
    }
    if settings.max_sections < 2 {
        return Err(SketchError::BadParameter {
            what: "max_sections",
            value: settings.max_sections as f64,
        });
    }
    let (a, b) = spine.curve.domain();
    let (min_bend_radius, at) = min_bend(spine)?;
    if min_bend_radius < radius {
        return Err(SketchError::TooTight {
            bend_radius: min_bend_radius,
            radius,
            at: (at - a) / (b - a),
        });
    }
    let frames = SpineFrames::new(spine)?;
    let rail = |v: f64| frame_rails(spine, &frames, radius, v);
    let mut params = vec![a, b];
    loop {
        let samples = params
            .iter()
            .map(|&v| rail(v))
            .collect::<Result<Vec<_>, _>>()?;
        let mut interp = Vec::with_capacity(5);
        for k in 0..5 {
            let pts: Vec<DVec3> = samples.iter().map(|s| s[k]).collect();
            interp.push(interpolate_natural_cubic(&pts, &params)?);
        }
        let mut errors = Vec::with_capacity(params.len() - 1);
        for w in params.windows(2) {
            let mut e: f64 = 0.0;
            for j in 1..=CHECKS_PER_INTERVAL {
                let v = w[0] + (w[1] - w[0]) * j as f64 / (CHECKS_PER_INTERVAL + 1) as f64;
                let want = rail(v)?;
                for k in 0..5 {
                    e = e.max((interp[k].point(v) - want[k]).length());
                }
            }
            errors.push(e);
        }
        let max_error = errors.iter().copied().fold(0.0, f64::max);
        let bad = errors.iter().filter(|&&e| e > settings.tolerance).count();
        if bad == 0 {
            return Ok(SectionPlan {
                params,
                max_error,
                min_bend_radius,
            });
        }
        if params.len() + bad > settings.max_sections {
            return Err(SketchError::TooManySections {
                max: settings.max_sections,
                error: max_error,
                tolerance: settings.tolerance,
            });
        }
        let mut next = Vec::with_capacity(params.len() + bad);
        for (i, w) in params.windows(2).enumerate() {
            next.push(w[0]);
            if errors[i] > settings.tolerance {
                next.push(0.5 * (w[0] + w[1]));
            }
        }
        next.push(b);
        params = next;
    }
}

/// A sketched spine ready for a GC: the simplified stroke (the points a
/// `gc_create` spine interpolates), its plane normal and the sections'
/// parameters on the spine those points make.
#[derive(Clone, Debug, PartialEq)]
pub struct SketchedSpine {
    /// Spine points (RDP-simplified stroke, projected into the plane).
    pub points: Vec<DVec3>,
    /// Unit normal of the spine plane.
    pub plane_normal: DVec3,
    /// Where the key sections go, and how well the tube then follows.
    pub plan: SectionPlan,
}

/// Points of a spine through which the interpolating spine stays within
/// `tol` of the stroke: the RDP-simplified stroke (the headset's pipeline,
/// [`fit_spine_stroke`]), plus, while the cubic through them strays
/// farther than `tol` from a resampled stroke point (it can overshoot
/// where RDP kept only a straight run's two ends next to a tight bend),
/// the farthest such point.
pub fn spine_points(
    stroke: &[DVec3],
    plane: &SketchPlane,
    tol: f64,
) -> Result<(Vec<DVec3>, Spine), SketchError> {
    let fit = fit_spine_stroke(stroke, plane, tol)?;
    let p2 = project_stroke(stroke, plane)?;
    let samples: Vec<DVec3> = resample(&p2, SPINE_SAMPLES, false)?
        .iter()
        .map(|q| plane.lift(*q))
        .collect();
    // RDP keeps samples unchanged; mark them.
    let mut keep = vec![false; samples.len()];
    let mut next = 0;
    for p in &fit.simplified {
        if let Some(i) = (next..samples.len()).find(|&i| samples[i] == *p) {
            keep[i] = true;
            next = i + 1;
        }
    }
    keep[0] = true;
    let last = samples.len() - 1;
    keep[last] = true;
    loop {
        let points: Vec<DVec3> = (0..samples.len())
            .filter(|&i| keep[i])
            .map(|i| samples[i])
            .collect();
        let spine = fit_spine(&points, plane.normal)?;
        let dense = spine.curve.polyline(16 * SPINE_SAMPLES);
        let (worst, dev) = samples
            .iter()
            .enumerate()
            .filter(|(i, _)| !keep[*i])
            .map(|(i, p)| (i, point_to_polyline(*p, &dense)))
            .fold(
                (None, 0.0),
                |acc, (i, d)| if d > acc.1 { (Some(i), d) } else { acc },
            );
        match worst {
            Some(i) if dev > tol => keep[i] = true,
            _ => return Ok((points, spine)),
        }
    }
}

fn point_to_polyline(p: DVec3, path: &[DVec3]) -> f64 {
    path.windows(2)
        .map(|w| {
            let ab = w[1] - w[0];
            let t = ((p - w[0]).dot(ab) / ab.length_squared().max(1e-300)).clamp(0.0, 1.0);
            (w[0] + ab * t - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The spine a stroke sketched in `plane` makes, and the key sections it
/// needs for sections reaching `radius` from it: the stroke is projected,
/// resampled and simplified by RDP (the same pipeline as the headset's
/// GC tool, [`fit_spine_stroke`]; [`spine_points`]), the spine
/// interpolates the simplified points, and [`section_params`] places the
/// sections.
pub fn sketch_spine(
    stroke: &[DVec3],
    plane: &SketchPlane,
    radius: f64,
    settings: &SectionSettings,
) -> Result<SketchedSpine, SketchError> {
    let (points, spine) = spine_points(stroke, plane, settings.stroke_tolerance)?;
    let plan = section_params(&spine, radius, settings)?;
    Ok(SketchedSpine {
        points,
        plane_normal: plane.normal,
        plan,
    })
}

/// Largest distance from the points of `stroke` (projected into `plane`)
/// to the polyline `path` (e.g. a tube's sampled axis): how far a result
/// strays from what was sketched.
pub fn stroke_deviation(stroke: &[DVec3], plane: &SketchPlane, path: &[DVec3]) -> f64 {
    let Ok(p2) = project_stroke(stroke, plane) else {
        return f64::INFINITY;
    };
    if path.len() < 2 || length(&p2, false) == 0.0 {
        return f64::INFINITY;
    }
    p2.iter()
        .map(|q| point_to_polyline(plane.lift(*q), path))
        .fold(0.0, f64::max)
}
