//! The tools by name: [`TOOL_NAMES`] and [`tool_named`], the one registry
//! both hosts and traces use.

use super::context::Tool;
use super::{brush_tool, csg_tool, curve_tool, gc_tool, object_tool};

/// The names [`tool_named`] knows: the object tool, the hand-gesture GC
/// tool (paper 1), and the controller tools of papers 2, 3 and 4.
pub const TOOL_NAMES: [&str; 5] = ["object", "gc", "csg", "curve", "sculpt"];

/// The tool called `name` (a trace header's or a host's choice).
pub fn tool_named(name: &str) -> Result<Box<dyn Tool>, UnknownTool> {
    match name {
        "object" => Ok(Box::new(object_tool::ObjectTool::default())),
        "curve" => Ok(Box::new(curve_tool::CurveNetworkTool::default())),
        "csg" => Ok(Box::new(csg_tool::CsgTool::default())),
        "sculpt" => Ok(Box::new(brush_tool::BrushTool::default())),
        "gc" => Ok(Box::new(gc_tool::GcTool::default())),
        other => Err(UnknownTool(other.to_string())),
    }
}

/// A tool name this build does not have.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown tool `{0}` (known: object, gc, csg, curve, sculpt)")]
pub struct UnknownTool(pub String);
