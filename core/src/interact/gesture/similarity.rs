//! [`Similarity`]: rotation, translation and uniform scale — the motions
//! hands can express — and how they act on object placements.

use crate::math::{DAffine3, DQuat, DVec3, Transform};

use crate::interact::input::Pose;

/// `p -> translate + rotate * (scale * p)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Similarity {
    /// Translation.
    pub translate: DVec3,
    /// Rotation (unit quaternion).
    pub rotate: DQuat,
    /// Uniform scale (> 0).
    pub scale: f64,
}

impl Default for Similarity {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Similarity {
    /// No motion.
    pub const IDENTITY: Similarity = Similarity {
        translate: DVec3::ZERO,
        rotate: DQuat::IDENTITY,
        scale: 1.0,
    };

    /// The rigid motion of a pose (local to parent).
    pub fn from_pose(p: &Pose) -> Similarity {
        Similarity {
            translate: p.position,
            rotate: p.orientation,
            scale: 1.0,
        }
    }

    /// Maps a point.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.translate + self.rotate * (p * self.scale)
    }

    /// Maps a direction (rotation only).
    pub fn apply_dir(&self, d: DVec3) -> DVec3 {
        self.rotate * d
    }

    /// `self` after `inner`.
    pub fn compose(&self, inner: &Similarity) -> Similarity {
        Similarity {
            translate: self.apply(inner.translate),
            rotate: (self.rotate * inner.rotate).normalize(),
            scale: self.scale * inner.scale,
        }
    }

    /// The inverse motion.
    pub fn inverse(&self) -> Similarity {
        let r = self.rotate.inverse();
        let s = 1.0 / self.scale;
        Similarity {
            translate: r * (-self.translate * s),
            rotate: r,
            scale: s,
        }
    }

    /// The motion `other` expressed in the frame this similarity maps
    /// from: `self^-1 * other * self`.
    pub fn conjugate(&self, other: &Similarity) -> Similarity {
        self.inverse().compose(&other.compose(self))
    }

    /// This motion applied after an object placement `t` (any per-axis
    /// scale; the result stays scale-rotate-translate because the motion's
    /// scale is uniform).
    pub fn then_transform(&self, t: &Transform) -> Transform {
        let rt = DQuat::from_array(t.rotate).normalize();
        let tt = DVec3::from_array(t.translate);
        Transform {
            translate: self.apply(tt).to_array(),
            rotate: (self.rotate * rt).normalize().to_array(),
            scale: (DVec3::from_array(t.scale) * self.scale).to_array(),
        }
    }

    /// As an affine matrix.
    pub fn to_affine(&self) -> DAffine3 {
        DAffine3::from_scale_rotation_translation(
            DVec3::splat(self.scale),
            self.rotate,
            self.translate,
        )
    }

    /// True when finite with a positive scale.
    pub fn is_valid(&self) -> bool {
        self.translate.is_finite()
            && self.rotate.is_finite()
            && self.scale.is_finite()
            && self.scale > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compose_inverse_conjugate() {
        let a = Similarity {
            translate: DVec3::new(1.0, 2.0, 3.0),
            rotate: DQuat::from_rotation_y(0.7),
            scale: 2.0,
        };
        let b = Similarity {
            translate: DVec3::new(-0.5, 0.0, 0.25),
            rotate: DQuat::from_rotation_x(-0.3),
            scale: 0.5,
        };
        let p = DVec3::new(0.3, -0.2, 0.9);
        assert!((a.compose(&b).apply(p) - a.apply(b.apply(p))).length() < 1e-12);
        assert!((a.inverse().apply(a.apply(p)) - p).length() < 1e-12);
        let c = a.conjugate(&b);
        assert!((c.apply(p) - a.inverse().apply(b.apply(a.apply(p)))).length() < 1e-12);
        let t = Transform {
            translate: [0.1, 0.2, 0.3],
            rotate: DQuat::from_rotation_z(0.4).to_array(),
            scale: [1.0, 2.0, 3.0],
        };
        let after = a.then_transform(&t).to_affine().unwrap();
        let before = t.to_affine().unwrap();
        assert!((after.transform_point3(p) - a.apply(before.transform_point3(p))).length() < 1e-12);
    }
}
