//! The tool framework: a [`Tool`] is a state machine that consumes
//! sanitized frames and produces preview state every frame and, when a
//! gesture completes, exactly one command (an op, undo or redo) — never one
//! per frame.
//!
//! Tools see the document read-only through a [`ToolContext`]; the
//! [`crate::interact::Session`] applies their commands to the log. Commands are the
//! doc module's [`ScriptCommand`](crate::doc::ScriptCommand), so a session's output is an op script.

pub(crate) mod brush_tool;
pub(crate) mod csg_tool;
pub(crate) mod ctl_input;
#[cfg(test)]
pub(crate) mod ctl_tool_tests;
pub(crate) mod curve_tool;
#[cfg(test)]
pub(crate) mod curve_tool_tests;
pub(crate) mod gc_tool;
pub(crate) mod object_tool;
pub(crate) mod pick;
pub mod snap;
#[cfg(test)]
pub(crate) mod tool_tests;

mod context;
mod preview;
mod registry;

pub(crate) use context::{lost_too_long, object_label};
pub use context::{Tool, ToolContext};
pub use preview::{
    BrushPreview, CsgPreview, MovingPreview, OperandPreview, Preview, PreviewRay, ToolPreview,
};
pub use registry::{tool_named, UnknownTool, TOOL_NAMES};
