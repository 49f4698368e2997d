//! Spine strokes: projected onto the spine plane, resampled, simplified by
//! RDP (the key points) and fitted by a least-squares cubic NURBS to a
//! tolerance (The NURBS Book §9.4).

use glam::DVec3;

use super::stroke::{length, rdp, resample};
use super::{project_stroke, SketchError, SketchPlane};
use crate::nurbs::{approximate_to_tolerance, NurbsCurve, ParamMethod};

/// Samples a spine stroke is resampled to.
pub const SPINE_SAMPLES: usize = 64;

/// A fitted spine stroke.
#[derive(Clone, Debug, PartialEq)]
pub struct SpineFit {
    /// The RDP-simplified stroke (in the plane, 3D), e.g. for `gc_create`.
    pub simplified: Vec<DVec3>,
    /// The least-squares NURBS through the resampled stroke.
    pub curve: NurbsCurve,
}

/// Fits an open spine stroke in `plane` with tolerance `tol` (model units):
/// RDP keeps points farther than `tol` from the simplified polyline, and
/// the NURBS passes within `tol` of every resampled point.
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
    let lifted: Vec<DVec3> = samples.iter().map(|q| plane.lift(*q)).collect();
    let curve = approximate_to_tolerance(&lifted, 3, tol, ParamMethod::ChordLength)?;
    Ok(SpineFit {
        simplified: simplified.iter().map(|q| plane.lift(*q)).collect(),
        curve,
    })
}
