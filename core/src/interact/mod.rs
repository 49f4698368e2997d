//! Host-agnostic interaction: everything between tracked input and ops
//! (issue 8; gestures of paper 1 §4, controller interfaces of papers 2–4).
//!
//! Both hosts (the Blender add-on and the OpenXR host) feed raw
//! [`InputFrame`]s into a [`Session`]; it sanitizes them, classifies hand
//! gestures, runs the active [`Tool`] and returns at most one
//! [`crate::doc::ScriptCommand`] per frame — an op when a gesture completes,
//! never one per frame — plus [`Preview`] state to render meanwhile.
//!
//! By stage, in the order a frame flows through them:
//! - [`input`]: per-frame input types, the one sanitizer (hosts use these
//!   types directly), controller bindings as data, controller button edges.
//! - [`gesture`]: the hand gesture classifier (paper 1, §4), the kinematic
//!   hand model, hands made from controllers, two-hand manipulation
//!   (handle bar, scaling, orienting grab) and hand motions as similarities.
//! - [`tools`]: the [`Tool`] trait, the tool registry ([`tool_named`],
//!   [`TOOL_NAMES`]), ray picking and one module per tool: object, the
//!   paper-1 GC tool, the paper-2 CSG, paper-3 curve and paper-4 brush tools.
//! - [`trace`]: recorded input traces and their replay.
//! - [`forms`]: ops as flat forms for a desktop host (fields, defaults as
//!   data, values to ops through the same sketch pipeline).
//! - `session`: one frame through the stages (sanitize, classify, run the
//!   active tool); a modeler session holds every tool and the off hand's
//!   [`palette`] that switches them.
//! - `testkit` (feature `testkit`): the scripted puppet, labelled hand
//!   sequences and the puppet scripts of the checked-in traces.
//!
//! The geometry systems' tools (generalized cylinders, SDF CSG, curve
//! styling, sculpting) plug in as further [`Tool`]s.

pub mod forms;
pub mod gesture;
pub mod input;
#[cfg(test)]
pub(crate) mod modeler_op_tests;
#[cfg(test)]
pub(crate) mod modeler_tests;
pub mod palette;
pub mod palette_draw;
mod presence;
// The headset reach table is a test of the tools (issue 36: test-only
// code out of the shipped library); read it in reach.rs.
#[cfg(test)]
pub(crate) mod reach;
mod session;
#[cfg(any(test, feature = "testkit"))]
pub mod testkit;
pub mod tools;
pub mod trace;

pub use gesture::bimanual::{
    two_hand_scale, HandleBar, ModelFrame, OrientGrab, MIN_BAR, SCALE_RANGE,
};
pub use gesture::controller_hand::{controller_gesture, controller_hand, point_tip_offset};
pub use gesture::handmodel::{hand_pose, HandParams, Rng};
pub use gesture::similarity::Similarity;
pub use gesture::{
    Gesture, GestureClassifier, GestureLabel, GestureSettings, GestureState, HandFeatures,
};
pub use input::bindings::{
    profile_named, ActionItem, ActionMap, ActionType, AxisRegion, Binding, Profile, ACTIONS,
    PROFILES,
};
pub use input::{
    Controller, ControllerButtons, ControllerSample, Frame, Hand, HandJoints, HandSample,
    HandSource, InputFrame, Joint, JointSample, Pose, Sanitizer, SanitizerSettings, SanitizerStats,
    JOINT_COUNT, STAGE_FROM_Z_UP,
};
pub use palette::{ChoiceGroup, PaletteAction, PaletteItem, PaletteView, Snap};
pub use palette_draw::{PaletteDraw, PaletteLabel, PaletteQuad, PaletteRole};
pub use session::Session;
pub use tools::brush_tool::{BrushPreset, BrushTool, BrushToolSettings};
pub use tools::csg_tool::{CsgTool, CsgToolSettings, SceneOperate};
pub use tools::curve_tool::{
    CurveMode, CurveNetworkTool, CurvePreview, CurveTarget, CurveToolSettings, DrawPlane,
    PatchTarget, SurfaceTool, SURFACE_MARGIN,
};
pub use tools::gc_tool::{GcPreview, GcTarget, GcTool, GcToolSettings};
pub use tools::object_tool::{ObjectTool, ObjectToolSettings};
pub use tools::pick::{pick, ray_mesh, ray_triangle, Hit, Ray};
pub use tools::{
    tool_named, BrushPreview, CsgPreview, MovingPreview, OperandPreview, Preview, PreviewRay, Tool,
    ToolContext, ToolPreview, UnknownTool, TOOL_NAMES,
};
pub use trace::{
    replay, ModelPlacement, Replay, Trace, TraceError, TraceHeader, TRACE_FORMAT, TRACE_VERSION,
};
