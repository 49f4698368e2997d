//! The modeling frame of two-handed drawing (paper §5.4): "the
//! non-dominant hand assists the modeling hand in drawing curves by
//! controlling the position and orientation of a modeling coordinate
//! system dynamically or by fixing it at a preferred place ...
//! alternatively, the non-dominant hand controls a virtual transparent
//! drawing plane onto which curves are projected, or it applies symmetry
//! planes".
//!
//! The logic, as values in and values out:
//!
//! - [`ModelingFrame`]: a rigid frame (origin and orientation in model
//!   space). Curves drawn in it live in its local coordinates.
//! - [`stroke_in_frame`]: a stroke sampled while the frame moved, each
//!   sample expressed in the frame as it was at that sample, so the stroke
//!   is drawn *on* the moving frame (as on paper turned by the other hand).
//! - [`ModelingFrame::follow`]: the frame held by the hand: grabbed at one
//!   hand pose, it moves rigidly with the hand; released, it stays.
//! - [`CurveNetwork::carried`]: what was drawn in a frame moves with it.
//!   B-splines are affine invariant and every patch (Coons and transfinite
//!   bases alike) is an affine combination of curve points, so moving the
//!   control points and turning the displacement coefficients by the
//!   linear part moves every curve, patch and mesh vertex exactly (to
//!   rounding; the tests check 1e-12), junctions included.
//! - [`project_to_drawing_plane`] and [`mirror_in_frame`]: the frame's
//!   `z = 0` plane as the drawing plane, its `x = 0` plane as a symmetry
//!   plane.
//!
//! - [`stroke_in_held_frame`]: what the `curve_draw_in_frame` op does: the
//!   network object is held in the frame, so its placement moves with the
//!   frame during the stroke and each sample lands in the network's own
//!   frame as it was placed at that sample.
//!
//! Frames are not stored in the network: a network object's `placement`
//! is where its frame holds it, a held frame's motion without drawing is a
//! `transform_by` of the network's placement, and `curve_draw_in_frame`
//! moves the placement by the frame's motion over its stroke. [`carried`]
//! moves the curves themselves (for hosts working without placements).
//!
//! [`carried`]: CurveNetwork::carried

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::math::{DAffine3, DQuat, DVec3};

use super::network::CurveNetwork;
use super::StylingError;

/// A rigid frame: origin and orientation in model space.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelingFrame {
    /// Origin (model units).
    #[schemars(extend("x-unit" = "m"))]
    pub origin: [f64; 3],
    /// Orientation quaternion `[x, y, z, w]` (normalized on use; must not
    /// be zero).
    pub rotation: [f64; 4],
}

impl Default for ModelingFrame {
    fn default() -> Self {
        Self::WORLD
    }
}

impl ModelingFrame {
    /// The model's own frame.
    pub const WORLD: Self = Self {
        origin: [0.0; 3],
        rotation: [0.0, 0.0, 0.0, 1.0],
    };

    /// A frame at `origin` turned by `rotation`.
    pub fn new(origin: DVec3, rotation: DQuat) -> Self {
        Self {
            origin: origin.to_array(),
            rotation: rotation.to_array(),
        }
    }

    fn quat(&self) -> Result<DQuat, StylingError> {
        if !self
            .origin
            .iter()
            .chain(&self.rotation)
            .all(|v| v.is_finite())
        {
            return Err(StylingError::NonFinite("modeling frame"));
        }
        let q = DQuat::from_array(self.rotation);
        if !(q.length_squared() > 1e-24) {
            return Err(StylingError::BadParameter(
                "modeling frame rotation is a zero quaternion; give [x, y, z, w] with w = 1 for no rotation",
            ));
        }
        Ok(q.normalize())
    }

    /// Checks the frame (finite, non-zero rotation).
    pub fn validate(&self) -> Result<(), StylingError> {
        self.quat().map(|_| ())
    }

    /// Local-to-model transform.
    pub fn affine(&self) -> Result<DAffine3, StylingError> {
        Ok(DAffine3::from_rotation_translation(
            self.quat()?,
            DVec3::from_array(self.origin),
        ))
    }

    /// The model-space motion that carries what is held in `self` to where
    /// it is held in `to`: `to ∘ self⁻¹`.
    pub fn motion_to(&self, to: &ModelingFrame) -> Result<DAffine3, StylingError> {
        Ok(to.affine()? * self.affine()?.inverse())
    }

    /// The frame held by a hand: grabbed when the hand was at `grab` and
    /// the frame at `held`, with the hand now at `hand`, the frame moves
    /// rigidly with the hand (`hand ∘ grab⁻¹ ∘ held`).
    pub fn follow(
        held: &ModelingFrame,
        grab: &ModelingFrame,
        hand: &ModelingFrame,
    ) -> Result<ModelingFrame, StylingError> {
        let m = hand.affine()? * grab.affine()?.inverse() * held.affine()?;
        let (_, q, t) = m.to_scale_rotation_translation();
        Ok(Self::new(t, q.normalize()))
    }
}

/// A stroke sampled while the frame moved, in the frame's local
/// coordinates: sample `i` (model space) is taken into `frames[i]`, or
/// into `frames[0]` when one frame is given for the whole stroke.
pub fn stroke_in_frame(
    samples: &[[f64; 3]],
    frames: &[ModelingFrame],
) -> Result<Vec<[f64; 3]>, StylingError> {
    if !(frames.len() == 1 || frames.len() == samples.len()) {
        return Err(StylingError::BadParameter(
            "give one modeling frame for the stroke or one per sample",
        ));
    }
    let inv: Vec<DAffine3> = frames
        .iter()
        .map(|f| f.affine().map(|a| a.inverse()))
        .collect::<Result<_, _>>()?;
    Ok(samples
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let m = inv[if inv.len() == 1 { 0 } else { i }];
            m.transform_point3(DVec3::from_array(*s)).to_array()
        })
        .collect())
}

/// Samples (model space) projected along the frame's `z` axis onto its
/// drawing plane (local `z = 0`), in model space.
pub fn project_to_drawing_plane(
    samples: &[[f64; 3]],
    frame: &ModelingFrame,
) -> Result<Vec<[f64; 3]>, StylingError> {
    in_frame(samples, frame, |l| l.with_z(0.0))
}

/// Samples (model space) mirrored across the frame's symmetry plane
/// (local `x = 0`), in model space.
pub fn mirror_in_frame(
    samples: &[[f64; 3]],
    frame: &ModelingFrame,
) -> Result<Vec<[f64; 3]>, StylingError> {
    in_frame(samples, frame, |l| DVec3::new(-l.x, l.y, l.z))
}

/// Samples (model space) changed by `local` in the frame's coordinates.
fn in_frame(
    samples: &[[f64; 3]],
    frame: &ModelingFrame,
    local: impl Fn(DVec3) -> DVec3,
) -> Result<Vec<[f64; 3]>, StylingError> {
    let m = frame.affine()?;
    let inv = m.inverse();
    Ok(samples
        .iter()
        .map(|s| {
            m.transform_point3(local(inv.transform_point3(DVec3::from_array(*s))))
                .to_array()
        })
        .collect())
}

impl CurveNetwork {
    /// The network moved by the affine map `m`: control points mapped,
    /// displacement coefficients turned by its linear part (exact, see the
    /// module doc). Node parameters are unchanged.
    pub fn transformed(&self, m: &DAffine3) -> Result<CurveNetwork, StylingError> {
        if !m.to_cols_array().iter().all(|v| v.is_finite()) {
            return Err(StylingError::NonFinite("network transform"));
        }
        let mut out = self.clone();
        for c in out.curves.iter_mut().flatten() {
            for p in &mut c.ctrl {
                *p = m.transform_point3(DVec3::from_array(*p)).to_array();
            }
        }
        for patch in &mut out.patches {
            for d in &mut patch.disp {
                *d = m.transform_vector3(DVec3::from_array(*d)).to_array();
            }
        }
        Ok(out)
    }

    /// The network drawn in a frame, carried by the frame moving from
    /// `from` to `to`.
    pub fn carried(
        &self,
        from: &ModelingFrame,
        to: &ModelingFrame,
    ) -> Result<CurveNetwork, StylingError> {
        self.transformed(&from.motion_to(to)?)
    }
}

/// A stroke drawn in a held modeling frame, taken into a network's own
/// frame (what the `curve_draw_in_frame` op fits and adds).
#[derive(Clone, Debug, PartialEq)]
pub struct HeldStroke {
    /// The stroke in the network's own frame.
    pub local: Vec<[f64; 3]>,
    /// Its mirror image across the frame's symmetry plane, in the
    /// network's own frame, when asked for.
    pub mirrored: Option<Vec<[f64; 3]>>,
    /// The rigid motion of the frame over the stroke (`F_last ∘ F_0⁻¹`,
    /// model space) as `(translation, rotation)`, or `None` when the frame
    /// did not move (one frame given, or the last equal to the first).
    pub motion: Option<(DVec3, DQuat)>,
}

/// The stroke `samples` (model space) drawn while the network placed at
/// `placement` (its own frame to model space, at the stroke's start) is
/// held in the modeling frame `frames` (one for the whole stroke, or one
/// per sample): the network moves with the frame, so sample `i` lands at
/// `P⁻¹ ∘ F_0 ∘ F_i⁻¹ (s_i)` in the network's own frame (the paper's
/// drawing on a sheet turned by the other hand). With `onto_plane` each
/// sample is first projected on its frame's drawing plane (local `z = 0`);
/// with `mirror` the stroke's image across the frame's symmetry plane
/// (local `x = 0`) is returned too. The network's placement after the
/// stroke is `motion ∘ P`.
pub fn stroke_in_held_frame(
    samples: &[[f64; 3]],
    frames: &[ModelingFrame],
    placement: &DAffine3,
    onto_plane: bool,
    mirror: bool,
) -> Result<HeldStroke, StylingError> {
    if !placement.to_cols_array().iter().all(|v| v.is_finite())
        || !(placement.matrix3.determinant().abs() > 1e-300)
    {
        return Err(StylingError::NonFinite("network placement"));
    }
    let (Some(first), Some(last)) = (frames.first(), frames.last()) else {
        return Err(StylingError::BadParameter(
            "give one modeling frame for the stroke or one per sample",
        ));
    };
    let in_frame = stroke_in_frame(samples, frames)?;
    let a = placement.inverse() * first.affine()?;
    let flat = |p: &[f64; 3]| {
        let mut l = DVec3::from_array(*p);
        if onto_plane {
            l.z = 0.0;
        }
        l
    };
    let local = in_frame
        .iter()
        .map(|p| a.transform_point3(flat(p)).to_array())
        .collect();
    let mirrored = mirror.then(|| {
        in_frame
            .iter()
            .map(|p| {
                let l = flat(p);
                a.transform_point3(DVec3::new(-l.x, l.y, l.z)).to_array()
            })
            .collect()
    });
    let motion = if frames.len() == 1 || first == last {
        None
    } else {
        let q0 = first.quat()?;
        let q1 = last.quat()?;
        let q = (q1 * q0.conjugate()).normalize();
        let t = DVec3::from_array(last.origin) - q * DVec3::from_array(first.origin);
        Some((t, q))
    };
    Ok(HeldStroke {
        local,
        mirrored,
        motion,
    })
}
