//! Weight functions (paper §4.3) and warp operators (§4.4).
//!
//! With normalized distance `dn = d / h`: linear `1 − dn`, smooth
//! `1 − dn²(3 − 2dn)`; 1 for `d <= 0` (inside the brush), 0 for `d >= h`,
//! times pressure in [0, 1]. A vertex moves by `x' = x + w(x)·f(x)`.
//!
//! Drag is the rigid increment of the brush frame from the previous sample
//! to the current one: `f(x) = p_i + Δo·(x − p_{i−1}) − x`, the motion of a
//! point rigidly attached to the brush (rotation about the brush position,
//! then its translation). The paper writes the rotation about `p_i`; the
//! two agree to first order, and this form makes a fully weighted region
//! move exactly rigidly with the brush. Weights are taken at the previous
//! pose (where the vertices were relative to the brush).

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

/// Weight falloff with normalized distance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Falloff {
    /// `1 − dn`: most intuitive for rotations.
    Linear,
    /// `1 − dn²(3 − 2dn)`: keeps the surface smoother.
    Smooth,
}

impl Falloff {
    /// The weight at signed distance `d` for influence size `h` and
    /// pressure in [0, 1].
    #[inline]
    pub fn weight(self, d: f64, h: f64, pressure: f64) -> f64 {
        if d <= 0.0 {
            return pressure;
        }
        if d >= h {
            return 0.0;
        }
        let dn = d / h;
        let w = match self {
            Self::Linear => 1.0 - dn,
            Self::Smooth => 1.0 - dn * dn * (3.0 - 2.0 * dn),
        };
        w * pressure
    }
}

/// A warp operator.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Warp {
    /// Rigid increment of the brush frame (push, pull, twist).
    Drag,
    /// `h · ∇d · delta`: away from the brush for `delta > 0` (explode),
    /// towards it for `delta < 0` (collapse).
    Explode {
        /// Signed amount per frame, as a fraction of `h`.
        delta: f64,
    },
    /// Local Laplacian smoothing: towards the centroid of the neighbours.
    Whittle,
}

/// The rigid motion from one brush pose to the next.
#[derive(Clone, Copy, Debug)]
pub struct DragIncrement {
    /// Previous brush position (rotation centre).
    pub from: DVec3,
    /// Current brush position.
    pub to: DVec3,
    /// Rotation increment `o_i · o_{i−1}⁻¹`.
    pub rotation: DQuat,
}

impl DragIncrement {
    /// Where a point rigidly attached to the brush goes.
    #[inline]
    pub fn apply(&self, x: DVec3) -> DVec3 {
        self.to + self.rotation * (x - self.from)
    }
}
