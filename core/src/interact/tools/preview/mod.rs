//! What a tool shows each frame ([`Preview`]): rays, the moving object,
//! the sketch, and the part only one tool has ([`ToolPreview`]), with the
//! curve and GC tools' parts beside it (the tools fill them; the preview
//! names them, never the tools).

mod curve;
mod gc;
mod shown;

pub use curve::{CurveMode, CurvePreview, CurveTarget, DrawPlane, PatchTarget, SurfaceTool};
pub use gc::{GcPreview, GcTarget};
pub use shown::{
    BrushPreview, CsgPreview, MovingPreview, OperandPreview, Preview, PreviewRay, ToolPreview,
};
