//! Host-agnostic interaction: everything between tracked input and ops
//! (issue 8; gestures of paper 1 §4, controller interfaces of papers 2–4).
//!
//! Both hosts (the Blender add-on and the OpenXR host) feed raw
//! [`InputFrame`]s into a [`Session`]; it sanitizes them, classifies hand
//! gestures, runs the active [`Tool`] and returns at most one
//! [`crate::doc::ScriptCommand`] per frame — an op when a gesture completes,
//! never one per frame — plus [`Preview`] state to render meanwhile.
//!
//! - `input`: per-frame input types and the sanitizing layer.
//! - `gesture`: the hand gesture classifier (paper 1, §4).
//! - `controller_hand`: hands made from controllers (buttons choose the
//!   gesture), for the hand-gesture tool where no hand is tracked.
//! - `handmodel`: a kinematic hand model, the classifier's labelled test set.
//! - `bimanual`: handle bar, two-hand scaling, one hand orienting the model.
//! - `bindings`: controller bindings as data (Blender's layout).
//! - `similarity`, `pick`: hand motions on placements; ray picking.
//! - `tool`, `object_tool`, `session`: the tool framework and the object
//!   tool (select, place, grab, move, rotate, scale, delete, copy, undo).
//! - `trace`, `puppet`: recorded input traces, their replay, and the
//!   scripted puppet that makes them.
//!
//! - `csg_tool`, `brush_tool` (with `ctl_input`): the controller tools of
//!   paper 2 (SDF CSG) and paper 4 (warp-brush sculpting).
//!
//! The geometry systems' tools (generalized cylinders, SDF CSG, curve
//! styling, sculpting) plug in as further [`Tool`]s.

mod bimanual;
mod bindings;
mod brush_tool;
mod controller_hand;
mod csg_tool;
mod ctl_input;
#[cfg(test)]
mod ctl_tool_tests;
#[cfg(test)]
mod ctl_traces;
mod curve_tool;
#[cfg(test)]
mod curve_tool_tests;
mod gc_tool;
mod gesture;
#[cfg(test)]
mod gesture_accuracy;
mod handmodel;
mod input;
mod object_tool;
mod pick;
mod puppet;
mod session;
mod similarity;
mod tool;
#[cfg(test)]
mod tool_tests;
mod trace;
#[cfg(test)]
mod trace_fixture;

pub use bimanual::{two_hand_scale, HandleBar, ModelFrame, OrientGrab, MIN_BAR, SCALE_RANGE};
pub use bindings::{
    profile_named, ActionItem, ActionMap, ActionType, AxisRegion, Binding, Profile, ACTIONS,
    PROFILES,
};
pub use brush_tool::{BrushPreset, BrushTool, BrushToolSettings};
pub use controller_hand::{controller_gesture, controller_hand, point_tip_offset};
pub use csg_tool::{CsgTool, CsgToolSettings, SceneOperate};
pub use curve_tool::{
    CurveMode, CurveNetworkTool, CurvePreview, CurveTarget, CurveToolSettings, DrawPlane,
};
pub use gc_tool::{
    mug_controller_trace, mug_trace, teapot_controller_trace, teapot_trace, GcPreview, GcTarget,
    GcTool, GcToolSettings,
};
pub use gesture::{
    score_sequence, Gesture, GestureClassifier, GestureLabel, GestureScore, GestureSettings,
    GestureState, HandFeatures,
};
pub use handmodel::{
    hand_pose, hand_sample, labelled_sequence, HandParams, LabelledFrame, Rng, SequenceSettings,
};
pub use input::{
    Controller, ControllerButtons, ControllerSample, Frame, Hand, HandJoints, HandSample,
    HandSource, InputFrame, Joint, JointSample, Pose, Sanitizer, SanitizerSettings, SanitizerStats,
    JOINT_COUNT,
};
pub use object_tool::{ObjectTool, ObjectToolSettings};
pub use pick::{pick, ray_mesh, ray_triangle, Hit, Ray};
pub use puppet::{Button, Puppet};
pub use session::Session;
pub use similarity::Similarity;
pub use tool::{
    apply_command, BrushPreview, MovingPreview, OperandPreview, Preview, PreviewRay, Tool,
    ToolContext,
};
pub use trace::{
    replay, tool_named, ModelPlacement, Replay, Trace, TraceError, TraceHeader, TOOL_NAMES,
    TRACE_FORMAT, TRACE_VERSION,
};
