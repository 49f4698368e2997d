//! Spine strokes: projected onto the spine plane, resampled and simplified
//! by RDP (the key points of the spine).
//!
//! The paper "approximates [the simplified stroke] using a NURBS curve"
//! (§4), and its spine *interpolates* the section centres (§3.1 eq. 3); a
//! GC op carries spine points, which `gc::fit_spine` interpolates. So the
//! spine is the cubic through the RDP points, and [`super::spine_points`]
//! adds stroke samples where that cubic strays farther than the tolerance
//! from the stroke: that is the approximation, checked. (A least-squares
//! fit of the stroke used to be computed here as well and was never
//! used: no op can carry it.)

use glam::DVec3;

use super::stroke::{length, rdp, resample};
use super::{project_stroke, SketchError, SketchPlane};

/// Samples a spine stroke is resampled to.
pub const SPINE_SAMPLES: usize = 64;

/// A simplified spine stroke.
#[derive(Clone, Debug, PartialEq)]
pub struct SpineFit {
    /// The RDP-simplified stroke (in the plane, 3D), e.g. for `gc_create`.
    pub simplified: Vec<DVec3>,
}

/// Simplifies an open spine stroke in `plane` with tolerance `tol` (model
/// units): RDP keeps points farther than `tol` from the simplified
/// polyline.
pub fn fit_spine_stroke(
    points: &[DVec3],
    plane: &SketchPlane,
    tol: f64,
) -> Result<SpineFit, SketchError> {
    if !tol.is_finite() || tol <= 0.0 {
        return Err(SketchError::BadParameter {
            what: "tolerance",
            value: tol,
        });
    }
    let p2 = project_stroke(points, plane)?;
    if p2.len() < 2 {
        return Err(SketchError::TooFewPoints {
            got: p2.len(),
            need: 2,
        });
    }
    if !(length(&p2, false) > tol) {
        return Err(SketchError::ZeroLength);
    }
    let samples = resample(&p2, SPINE_SAMPLES, false)?;
    let simplified = rdp(&samples, tol);
    Ok(SpineFit {
        simplified: simplified.iter().map(|q| plane.lift(*q)).collect(),
    })
}
