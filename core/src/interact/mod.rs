//! Host-agnostic interaction: everything between tracked input and ops.
//!
//! Both hosts (the Blender add-on and the OpenXR host) feed raw
//! [`InputFrame`]s in; the interaction layer sanitizes them, classifies hand
//! gestures, runs the tool state machines and emits [`crate::doc::Op`]s, one
//! per completed gesture, plus preview state to render while a gesture is in
//! progress.
//!
//! - `input`: per-frame input types and the sanitizing layer.
//! - `bimanual`: handle bar, two-hand scaling, one hand orienting the model.
//! - `gesture`: the hand gesture classifier (paper 1, §4).
//! - `handmodel`: a kinematic hand model, the classifier's labelled test set.

mod bimanual;
mod gesture;
#[cfg(test)]
mod gesture_accuracy;
mod handmodel;
mod input;

pub use bimanual::{two_hand_scale, HandleBar, ModelFrame, OrientGrab, MIN_BAR, SCALE_RANGE};
pub use gesture::{
    score_sequence, Gesture, GestureClassifier, GestureLabel, GestureScore, GestureSettings,
    GestureState, HandFeatures,
};
pub use handmodel::{
    hand_pose, hand_sample, labelled_sequence, HandParams, LabelledFrame, Rng, SequenceSettings,
};
pub use input::{
    Controller, ControllerButtons, ControllerSample, Frame, Hand, HandJoints, HandSample,
    InputFrame, Joint, JointSample, Pose, Sanitizer, SanitizerSettings, JOINT_COUNT,
};
