//! What the curve tool shows ([`CurvePreview`]) and the types it is made
//! of: the held [`DrawPlane`], the [`CurveMode`] and [`SurfaceTool`] the
//! pointer pose picks, and the pointed curve or patch. Here, on the
//! preview side, so that [`super::ToolPreview`] names them without the
//! preview importing the tool that fills them (issue 36).

use crate::doc::ObjectId;
use crate::math::DVec3;
use crate::styling::select::{CurveTool as TableTool, PatchPoint};

/// A plane held by the non-dominant hand (model space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawPlane {
    /// A point on it (the grip position).
    pub origin: DVec3,
    /// Unit normal (the hand's aim direction).
    pub normal: DVec3,
}

impl DrawPlane {
    pub(in crate::interact::tools) fn project(&self, p: DVec3) -> DVec3 {
        p - self.normal * (p - self.origin).dot(self.normal)
    }

    pub(in crate::interact::tools) fn mirror(&self, p: DVec3) -> DVec3 {
        crate::math::reflect(p, self.origin, self.normal)
    }
}

/// A surface tool of paper 3 §4.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceTool {
    /// `surface_smooth`.
    Smooth,
    /// `surface_sharpen`.
    Sharpen,
    /// `surface_pull` at the pointed point.
    Pull,
}

/// What the trigger starts (idle) or is doing (held).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveMode {
    /// Draw a new curve.
    Draw,
    /// A Table 1 tool on the pointed curve (`AttachNewCurve` draws).
    Edit(TableTool),
    /// `curve_attract` on the pointed curve.
    Attract,
    /// A surface tool on the pointed patch.
    Surface(SurfaceTool),
}

impl CurveMode {
    /// What the headset shows next to the pen.
    pub fn label(&self) -> &'static str {
        match self {
            CurveMode::Draw | CurveMode::Edit(TableTool::AttachNewCurve) => "draw",
            CurveMode::Edit(TableTool::SmoothSegment) => "smooth curve",
            CurveMode::Edit(TableTool::SharpenSegment) => "sharpen curve",
            CurveMode::Edit(TableTool::EditDataPoint) => "pull curve",
            CurveMode::Attract => "attract curve",
            CurveMode::Surface(SurfaceTool::Smooth) => "smooth surface",
            CurveMode::Surface(SurfaceTool::Sharpen) => "sharpen surface",
            CurveMode::Surface(SurfaceTool::Pull) => "pull surface",
        }
    }
}

/// The patch point the pen points at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchTarget {
    /// The network.
    pub network: ObjectId,
    /// The patch point (model space; distance in model units).
    pub at: PatchPoint,
    /// Tip distance to it (metres).
    pub distance: f64,
}

/// The curve point the pen points at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveTarget {
    /// The network.
    pub network: ObjectId,
    /// The curve index.
    pub curve: usize,
    /// Parameter of the pointed point (t0).
    pub t0: f64,
    /// The pointed point (model space).
    pub point: DVec3,
    /// Tip distance to it (metres).
    pub distance: f64,
    /// Angle between the pen and the curve tangent (degrees).
    pub angle_deg: f64,
    /// What Table 1 selects there.
    pub tool: Option<TableTool>,
}

/// The curve tool's preview state.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurvePreview {
    /// The pen tip (model space), when tracked.
    pub tip: Option<DVec3>,
    /// The mode a press would start, or the held stroke's mode.
    pub mode: Option<CurveMode>,
    /// The pointed curve point (for a held edit: as at the press).
    pub target: Option<CurveTarget>,
    /// The pointed patch point, when a forced surface tool would act on it.
    pub patch: Option<PatchTarget>,
    /// The drawing plane in use or offered.
    pub plane: Option<DrawPlane>,
    /// The symmetry plane in use or offered.
    pub symmetry: Option<DrawPlane>,
    /// The pointer path of a held edit (model space).
    pub path: Vec<DVec3>,
    /// A stroke is frozen by lost tracking.
    pub frozen: bool,
}
