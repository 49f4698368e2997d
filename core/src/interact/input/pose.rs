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
}
