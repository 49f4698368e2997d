//! Per-frame input as hosts deliver it ([`InputFrame`]), and the
//! sanitizing layer ([`Sanitizer`]) that every tool sits behind.
//!
//! Coordinates are the OpenXR stage space: metres, +Y up, right-handed.
//! Hands are indexed by [`Hand`] (`0` left, `1` right).
//!
//! Raw samples carry validity flags exactly as OpenXR reports them
//! (`XrSpaceLocationFlags`, `XrHandJointLocationEXT::locationFlags`, the
//! `isActive` of each action). The sanitizer turns a raw frame into a
//! [`Frame`] in which an untracked or non-finite sample is simply absent
//! (`None`), so a tool cannot read a NaN by mistake: a sample that fails is
//! dropped and never changes any state downstream.
//!
//! This is the one sanitizer both hosts use: the OpenXR host copies what
//! the runtime reported (poses with their VALID bits, action values,
//! joints) into an [`InputFrame`] without judging it, and the Blender
//! add-on does the same with Blender's XR events. The checks and the
//! counts of what was dropped ([`SanitizerStats`]) live here only.
//!
//! **Hands versus controllers** (issue 16): runtimes such as Monado and
//! SteamVR with Index controllers report hand joints *derived from the
//! controller* (finger curls from the grip sensors) through
//! `XR_EXT_hand_tracking`. When a hand sample and valid controller buttons
//! arrive together, the buttons are the user's intent, so the sanitizer
//! drops the hand and tools that read hands make one from the buttons
//! ([`crate::interact::controller_hand`]), unless the runtime said the joints come
//! from optical tracking ([`HandSource::Optical`], from
//! `XR_EXT_hand_tracking_data_source`).
//!
//! Traces store non-finite numbers (a faulty runtime's NaN) as the strings
//! `"NaN"`, `"inf"` and `"-inf"`, since JSON has no such numbers; finite
//! numbers are written exactly as before (shortest round-trip form).

pub(crate) mod bindings;

mod frame;
mod joints;
mod num;
mod pose;
mod raw;
mod sanitizer;
#[cfg(test)]
mod tests;

pub use frame::{Controller, Frame, HandJoints};
pub use joints::{HandSample, HandSource, Joint, JointSample, JOINT_COUNT};
pub use pose::{Hand, Pose, STAGE_FROM_Z_UP};
pub use raw::{ControllerButtons, ControllerSample, InputFrame};
pub use sanitizer::{Sanitizer, SanitizerSettings, SanitizerStats};
