//! Placed components: resampling a component's local SDF into the scene
//! grid at `T⁻¹p` (paper 2 §5.2), and two-hand scaling (§4.3, eq. 1).
//!
//! **Non-uniform scale.** With `T = translate · rotate · scale(s)`, the
//! local value `φ_l(T⁻¹p)` is a distance in local units. Under a uniform
//! scale `s`, `s · φ_l` is the world distance. Under a non-uniform scale it
//! is not a distance at all; we use `min|s_i| · φ_l(T⁻¹p)`. Its zero set is
//! exactly the scaled surface, and since `|∇(φ_l ∘ T⁻¹)| ≤ 1 / min|s_i|`,
//! the corrected field is 1-Lipschitz: it never overestimates the true
//! distance. That keeps marching cubes' vertex placement sensible (the
//! zero crossing is interpolated from values of the right sign and order of
//! magnitude) and makes the far-brick test of the fusion conservative
//! (a brick is only skipped when its centre is provably farther from the
//! surface than the brick's radius plus the band).

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::analytic::solid_distance;
use super::dense::GridField;
use super::fold::FoldField;
use super::SdfError;
use crate::math::{DAffine3, DVec3, Transform};
use crate::solid::SolidShape;

/// Two-hand scale ratios are clamped to this range (paper §4.3).
pub const TWO_HAND_RATIO: [f64; 2] = [0.4, 4.0];

/// The local field of a component, ready to sample.
#[derive(Clone, Debug)]
pub enum LocalField {
    /// An exact analytic distance.
    Solid(SolidShape),
    /// A precomputed grid, trilinearly interpolated.
    Grid(Arc<GridField>),
    /// The fold of placed fields: a copy of a fused result
    /// ([`super::reuse`]), exact where a grid sampled from the result's
    /// mesh would carry its chords twice.
    Fold(Arc<FoldField>),
}

impl LocalField {
    /// The local box outside which the value is +infinity (the band).
    pub fn local_bounds(&self) -> (DVec3, DVec3) {
        match self {
            LocalField::Solid(s) => {
                let h = DVec3::from_array(s.half_extents());
                // A margin so the box holds the whole band around the shape.
                let m = h.max_element() * 0.25;
                (-h - DVec3::splat(m), h + DVec3::splat(m))
            }
            LocalField::Grid(g) => g.sdf.bounds(),
            LocalField::Fold(x) => x.bounds,
        }
    }

    /// The Lipschitz bound of the local field (trilinear interpolation of a
    /// distance sampled on a grid can reach √3 along a diagonal).
    pub fn lipschitz(&self) -> f64 {
        match self {
            LocalField::Solid(_) => 1.0,
            LocalField::Grid(_) => 3f64.sqrt(),
            LocalField::Fold(x) => x.lipschitz(),
        }
    }

    /// The local value at `p`, or `None` outside the local box.
    #[inline]
    pub fn sample(&self, p: DVec3) -> Option<f64> {
        match self {
            LocalField::Solid(s) => Some(solid_distance(s, p)),
            LocalField::Grid(g) => g.sdf.sample(p),
            LocalField::Fold(x) => Some(x.value(p)),
        }
    }
}

/// A component under a placement, as the fusion samples it.
#[derive(Clone, Debug)]
pub struct PlacedField {
    /// The local field.
    pub field: LocalField,
    /// Local → world.
    pub forward: DAffine3,
    /// World → local.
    pub inverse: DAffine3,
    /// `min |s_i|`: the non-uniform scale correction.
    pub scale_min: f64,
    /// The local box.
    pub local_box: (DVec3, DVec3),
    /// The world box of the transformed local box.
    pub world_box: (DVec3, DVec3),
    /// For a grid field: world → grid index coordinates (the inverse
    /// transform and the grid's origin and step in one affine).
    to_index: Option<DAffine3>,
}

impl PlacedField {
    /// Places `field` by `t`, which must be valid (finite, non-singular).
    pub fn new(field: LocalField, t: &Transform) -> Result<Self, SdfError> {
        let m = t.to_affine()?;
        let det = m.matrix3.determinant();
        if !det.is_finite() || det.abs() < 1e-15 {
            return Err(SdfError::SingularTransform);
        }
        let inverse = m.inverse();
        let scale_min = t
            .scale
            .iter()
            .map(|s| s.abs())
            .fold(f64::INFINITY, f64::min);
        let local_box = field.local_bounds();
        let (lo, hi) = local_box;
        let mut wlo = DVec3::splat(f64::INFINITY);
        let mut whi = DVec3::splat(f64::NEG_INFINITY);
        for c in 0..8 {
            let p = DVec3::new(
                if c & 1 == 0 { lo.x } else { hi.x },
                if c & 2 == 0 { lo.y } else { hi.y },
                if c & 4 == 0 { lo.z } else { hi.z },
            );
            let w = m.transform_point3(p);
            wlo = wlo.min(w);
            whi = whi.max(w);
        }
        let to_index = match &field {
            LocalField::Grid(g) => {
                let s = 1.0 / g.sdf.step;
                Some(
                    DAffine3::from_scale(DVec3::splat(s))
                        * DAffine3::from_translation(-DVec3::from_array(g.sdf.origin))
                        * inverse,
                )
            }
            LocalField::Solid(_) | LocalField::Fold(_) => None,
        };
        Ok(Self {
            field,
            forward: m,
            inverse,
            scale_min,
            local_box,
            world_box: (wlo, whi),
            to_index,
        })
    }

    /// An estimate of the placed surface's area (model units²), for the
    /// budgets ([`super::budget`]): a mesh component's own area times the
    /// largest axis scale squared; an analytic solid's box (a bound for
    /// the convex ones).
    pub fn surface_area(&self) -> f64 {
        let m = self.forward.matrix3;
        let s = [m.x_axis.length(), m.y_axis.length(), m.z_axis.length()];
        match &self.field {
            LocalField::Grid(g) => {
                let smax = s.iter().copied().fold(0.0, f64::max);
                g.surface_area * smax * smax
            }
            LocalField::Fold(x) => {
                let smax = s.iter().copied().fold(0.0, f64::max);
                x.area * smax * smax
            }
            LocalField::Solid(shape) => {
                let h = shape.half_extents();
                let e = [0, 1, 2].map(|a| 2.0 * h[a] * s[a]);
                2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
            }
        }
    }

    /// The corrected world value at world point `p`, or `None` outside the
    /// component's box (+infinity).
    #[inline]
    pub fn value(&self, p: DVec3) -> Option<f64> {
        match (&self.field, &self.to_index) {
            (LocalField::Grid(g), Some(a)) => g
                .sdf
                .sample_index(a.transform_point3(p))
                .map(|v| v * self.scale_min),
            _ => {
                let q = self.inverse.transform_point3(p);
                self.field.sample(q).map(|v| v * self.scale_min)
            }
        }
    }

    /// The corrected world value at `p` and its gradient (world units),
    /// exact for a grid field (the derivative of its trilinear cell);
    /// `None` outside the box, and for analytic solids and folds (whose
    /// callers difference [`Self::value`]).
    #[inline]
    pub fn value_gradient(&self, p: DVec3) -> Option<(f64, DVec3)> {
        let (LocalField::Grid(g), Some(a)) = (&self.field, &self.to_index) else {
            return None;
        };
        let (v, gu) = g.sdf.sample_gradient_index(a.transform_point3(p))?;
        // d/dp of f(A p + c) is Aᵀ ∇f.
        Some((
            v * self.scale_min,
            a.matrix3.transpose() * gu * self.scale_min,
        ))
    }

    /// The sign (`+1` or `-1`) shared by every world value within the ball
    /// of radius `r` around `p`, when each of them is provably beyond
    /// `band` in magnitude; `None` when that cannot be shown.
    ///
    /// The field is evaluated at the point `q` of the component's box
    /// nearest to `T⁻¹p` (values outside the box are +band anyway); every
    /// point of the ball that lies in the box is within `r + |p − Tq|` of
    /// `Tq`, so the Lipschitz bound `lip` proves the rest.
    pub fn far_sign(&self, p: DVec3, r: f64, band: f64) -> Option<f64> {
        if let LocalField::Fold(x) = &self.field {
            // The ball's image is within `r / scale_min` in the local
            // frame, where values are world ones over `scale_min`.
            let q = self.inverse.transform_point3(p);
            return x.far_sign(q, r / self.scale_min, band / self.scale_min);
        }
        let lip = self.field.lipschitz();
        let q = self.inverse.transform_point3(p);
        let (lo, hi) = self.local_box;
        let qc = q.clamp(lo, hi);
        let v = self.field.sample(qc)? * self.scale_min;
        let d = if qc == q {
            0.0
        } else {
            (self.forward.transform_point3(qc) - p).length()
        };
        if v >= lip * (r + d) + band {
            return Some(1.0);
        }
        let rl = r / self.scale_min;
        let ball_inside = qc == q && (q - lo).min_element() >= rl && (hi - q).min_element() >= rl;
        if ball_inside && v <= -(lip * r + band) {
            return Some(-1.0);
        }
        None
    }
}

/// Which axis a two-hand scale acts on (paper §4.3: X, Y, Z or A).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ScaleAxis {
    /// The component's local X.
    X,
    /// The component's local Y.
    Y,
    /// The component's local Z.
    Z,
    /// All three (isotropic).
    Uniform,
}

/// The unclamped two-hand ratio of eq. 1: the hands' distance now over
/// their distance when both grabs began.
pub fn two_hand_raw_ratio(old: [[f64; 3]; 2], new: [[f64; 3]; 2]) -> Result<f64, SdfError> {
    let all = old.iter().chain(new.iter()).flatten();
    if all.clone().any(|x| !x.is_finite()) {
        return Err(SdfError::NonFiniteHands);
    }
    let d0 = DVec3::from_array(old[0]).distance(DVec3::from_array(old[1]));
    let d1 = DVec3::from_array(new[0]).distance(DVec3::from_array(new[1]));
    if d0 < 1e-6 {
        return Err(SdfError::HandsTooClose { distance: d0 });
    }
    Ok(d1 / d0)
}

/// The two-hand scale ratio of eq. 1 for one gesture, clamped to
/// [`TWO_HAND_RATIO`]. Across gestures the clamp holds against the
/// operand's reference scale: see [`two_hand_scale`].
pub fn two_hand_ratio(old: [[f64; 3]; 2], new: [[f64; 3]; 2]) -> Result<f64, SdfError> {
    Ok(two_hand_raw_ratio(old, new)?.clamp(TWO_HAND_RATIO[0], TWO_HAND_RATIO[1]))
}

/// The scale after a two-hand gesture (§4.3) on `axis`: the current
/// `scale` times the gesture's ratio, with each scaled axis kept within
/// [`TWO_HAND_RATIO`] of `reference` (the scale before the first two-hand
/// gesture), so that no sequence of gestures goes beyond the paper's
/// [0.4, 4] (two gestures used to reach 16x).
pub fn two_hand_scale(
    scale: [f64; 3],
    reference: [f64; 3],
    axis: ScaleAxis,
    hands_start: [[f64; 3]; 2],
    hands_end: [[f64; 3]; 2],
) -> Result<[f64; 3], SdfError> {
    let r = two_hand_raw_ratio(hands_start, hands_end)?;
    let mut out = scale;
    let axes: &[usize] = match axis {
        ScaleAxis::X => &[0],
        ScaleAxis::Y => &[1],
        ScaleAxis::Z => &[2],
        ScaleAxis::Uniform => &[0, 1, 2],
    };
    for &a in axes {
        let f = (scale[a] * r / reference[a]).clamp(TWO_HAND_RATIO[0], TWO_HAND_RATIO[1]);
        out[a] = reference[a] * f;
    }
    Ok(out)
}
