//! What a host reads in one frame, unsanitized: controller buttons and
//! axes, controller samples and the whole [`InputFrame`] (serialized in
//! traces; non-finite numbers survive the round trip).

use serde::{Deserialize, Serialize};

use super::joints::HandSample;
use super::num;
use super::pose::Pose;

/// Raw controller buttons and axes, named by the actions of
/// `interact::input::bindings` (hosts fill them through the binding map).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ControllerButtons {
    /// `select` (trigger) value in `[0, 1]`.
    #[serde(skip_serializing_if = "is_zero", with = "num::f64")]
    pub select: f64,
    /// `grab` (squeeze/grip) value in `[0, 1]`.
    #[serde(skip_serializing_if = "is_zero", with = "num::f64")]
    pub grab: f64,
    /// `primary` button (A / X) pressed.
    #[serde(skip_serializing_if = "is_false")]
    pub primary: bool,
    /// `secondary` button (B / Y) pressed.
    #[serde(skip_serializing_if = "is_false")]
    pub secondary: bool,
    /// `menu` button pressed.
    #[serde(skip_serializing_if = "is_false")]
    pub menu: bool,
    /// `stick` (thumbstick or trackpad) `[x, y]`, each in `[-1, 1]`.
    #[serde(skip_serializing_if = "is_zero2", with = "num::arr2")]
    pub stick: [f64; 2],
}

// Exact comparisons: a default value is left out of traces, anything else
// (including -0.0 and NaN) is written.
pub(super) fn is_zero(x: &f64) -> bool {
    x.to_bits() == 0
}

pub(super) fn is_zero2(x: &[f64; 2]) -> bool {
    is_zero(&x[0]) && is_zero(&x[1])
}

pub(super) fn is_false(b: &bool) -> bool {
    !*b
}

/// One raw controller sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ControllerSample {
    /// The grip pose.
    pub grip: Pose,
    /// Grip pose valid.
    pub grip_valid: bool,
    /// The aim pose (the ray origin and direction, -Z).
    pub aim: Pose,
    /// Aim pose valid.
    pub aim_valid: bool,
    /// Buttons and axes.
    pub buttons: ControllerButtons,
    /// Buttons and axes valid (the controller is connected and the action
    /// set is active).
    pub buttons_valid: bool,
}

/// Everything a host reads in one frame. Any part may be missing or
/// invalid; the [`Sanitizer`](super::Sanitizer) decides what is usable.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InputFrame {
    /// Predicted display time in seconds; must increase from frame to frame.
    #[serde(with = "num::f64")]
    pub time: f64,
    /// The head (view) pose, if located.
    pub head: Option<Pose>,
    /// Hand joints, left and right, if the runtime reports them.
    pub hands: [Option<HandSample>; 2],
    /// Controllers, left and right, if present.
    pub controllers: [Option<ControllerSample>; 2],
}
