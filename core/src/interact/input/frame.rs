//! What the sanitizer hands on: [`HandJoints`], [`Controller`] and
//! [`Frame`], only usable data and the time step since the last frame.

use super::joints::{Joint, JOINT_COUNT};
use super::pose::{Hand, Pose};
use super::raw::ControllerButtons;
use crate::math::DVec3;

/// A sanitized hand: joint positions of the tracked joints. A joint that
/// was invalid or non-finite is `None`.
#[derive(Clone, Debug, PartialEq)]
pub struct HandJoints {
    /// Joint poses, indexed by [`Joint`].
    pub joints: [Option<Pose>; JOINT_COUNT],
}

impl HandJoints {
    /// The position of `j`, if tracked.
    pub fn pos(&self, j: Joint) -> Option<DVec3> {
        self.joints[j.index()].map(|p| p.position)
    }

    /// The pose of `j`, if tracked.
    pub fn pose(&self, j: Joint) -> Option<Pose> {
        self.joints[j.index()]
    }
}

/// A sanitized controller. Poses are present only when valid and finite;
/// buttons only when valid, finite and (after clamping) in range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controller {
    /// Grip pose.
    pub grip: Option<Pose>,
    /// Aim pose.
    pub aim: Option<Pose>,
    /// Buttons and axes.
    pub buttons: Option<ControllerButtons>,
    /// The grip moved faster than [`SanitizerSettings::max_speed`](super::SanitizerSettings::max_speed) since the
    /// last accepted sample: a locomotion teleport or a tracking glitch.
    /// Tools must not treat the jump as hand motion.
    pub teleported: bool,
}

/// A sanitized frame: only usable data, and the time step since the last
/// accepted frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Time in seconds.
    pub time: f64,
    /// Seconds since the previous accepted frame (0 for the first).
    pub dt: f64,
    /// Head pose.
    pub head: Option<Pose>,
    /// Hands, left and right.
    pub hands: [Option<HandJoints>; 2],
    /// Controllers, left and right.
    pub controllers: [Option<Controller>; 2],
}

impl Frame {
    /// The hand `h`.
    pub fn hand(&self, h: Hand) -> Option<&HandJoints> {
        self.hands[h.index()].as_ref()
    }

    /// The controller `h`.
    pub fn controller(&self, h: Hand) -> Option<&Controller> {
        self.controllers[h.index()].as_ref()
    }
}
