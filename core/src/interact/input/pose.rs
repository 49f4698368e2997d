//! [`Hand`] and [`Pose`]: which hand, and a rigid pose (position and unit
//! quaternion) in the units and frame the host reports.

use serde::{Deserialize, Serialize};

use super::num;
use crate::math::{DQuat, DVec3};

/// Left or right.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Hand {
    /// The left hand (index 0).
    Left,
    /// The right hand (index 1).
    Right,
}

impl Hand {
    /// Both hands, left first.
    pub const BOTH: [Hand; 2] = [Hand::Left, Hand::Right];

    /// 0 for left, 1 for right.
    pub fn index(self) -> usize {
        match self {
            Hand::Left => 0,
            Hand::Right => 1,
        }
    }

    /// The other hand.
    pub fn other(self) -> Hand {
        match self {
            Hand::Left => Hand::Right,
            Hand::Right => Hand::Left,
        }
    }
}

/// A rigid pose: position and orientation (a unit quaternion).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position in metres (`"p"` in traces).
    #[serde(rename = "p", with = "num::vec3")]
    pub position: DVec3,
    /// Orientation `[x, y, z, w]` (`"q"` in traces).
    #[serde(rename = "q", with = "num::quat")]
    pub orientation: DQuat,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// At the origin, unrotated.
    pub const IDENTITY: Pose = Pose {
        position: DVec3::ZERO,
        orientation: DQuat::IDENTITY,
    };

    /// A pose at `position` with `orientation`.
    pub fn new(position: DVec3, orientation: DQuat) -> Self {
        Self {
            position,
            orientation,
        }
    }

    /// True when every component is finite and the quaternion has a usable
    /// length (it is normalized by [`Pose::sanitized`]).
    pub fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.orientation.is_finite()
            && self.orientation.length_squared() > 1e-12
    }

    /// The pose with its quaternion normalized, or `None` if it is not
    /// finite.
    pub fn sanitized(&self) -> Option<Pose> {
        self.is_finite().then(|| Pose {
            position: self.position,
            orientation: self.orientation.normalize(),
        })
    }

    /// The pose's forward direction, OpenXR's -Z.
    pub fn forward(&self) -> DVec3 {
        self.orientation * DVec3::NEG_Z
    }

    /// Maps a point from this pose's local frame to the parent frame.
    pub fn transform_point(&self, p: DVec3) -> DVec3 {
        self.position + self.orientation * p
    }

    /// `self` after `inner`: the pose of `inner` given in this pose's frame.
    pub fn compose(&self, inner: &Pose) -> Pose {
        Pose {
            position: self.transform_point(inner.position),
            orientation: (self.orientation * inner.orientation).normalize(),
        }
    }

    /// The inverse pose.
    pub fn inverse(&self) -> Pose {
        let q = self.orientation.inverse();
        Pose {
            position: q * -self.position,
            orientation: q,
        }
    }

    /// The stage pose of a pose given in a Z-up world (Blender's, and the
    /// model's own axes), position in metres: `(x, y, z)` becomes
    /// `(x, z, -y)` and the orientation is turned by [`STAGE_FROM_Z_UP`].
    /// Both hosts' conversion, written once (issue 36).
    pub fn from_z_up(position: DVec3, orientation: DQuat) -> Pose {
        Pose {
            position: DVec3::new(position.x, position.z, -position.y),
            orientation: STAGE_FROM_Z_UP * orientation,
        }
    }

    /// The inverse of [`Pose::from_z_up`]: this stage pose's position and
    /// orientation in the Z-up world.
    pub fn to_z_up(&self) -> (DVec3, DQuat) {
        let p = self.position;
        (
            DVec3::new(p.x, -p.z, p.y),
            STAGE_FROM_Z_UP.conjugate() * self.orientation,
        )
    }
}

/// The rotation from a Z-up world to the Y-up OpenXR stage: a quarter
/// turn about `x` (`-90°`), written exactly (no sine or cosine, so the
/// same bits on every platform).
pub const STAGE_FROM_Z_UP: DQuat = DQuat::from_xyzw(
    -std::f64::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f64::consts::FRAC_1_SQRT_2,
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn z_up_poses_reach_the_stage_and_come_back() {
        // Blender's +Z (up) is the stage's +Y, its +Y (away) the stage's -Z.
        let up = Pose::from_z_up(DVec3::new(0.0, 0.0, 1.5), DQuat::IDENTITY);
        assert!((up.position - DVec3::new(0.0, 1.5, 0.0)).length() < 1e-15);
        let away = Pose::from_z_up(DVec3::Y, DQuat::IDENTITY);
        assert!((away.position - DVec3::NEG_Z).length() < 1e-15);
        // The orientation turns as the positions do.
        assert!((up.orientation * DVec3::Z - DVec3::Y).length() < 1e-15);
        let (p, q) = (DVec3::new(0.3, -1.2, 0.8), DQuat::from_rotation_y(0.7));
        let (p2, q2) = Pose::from_z_up(p, q).to_z_up();
        assert!(
            (p2 - p).length() < 1e-15 && q2.abs_diff_eq(q, 1e-15),
            "{p2} {q2}"
        );
    }
}
