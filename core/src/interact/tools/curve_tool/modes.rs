//! What the curve tool works on and shows: the held [`DrawPlane`], the
//! [`CurveMode`] and [`SurfaceTool`] the pointer pose picks, the pointed
//! curve or patch, the pen and the stroke being drawn, and
//! [`CurvePreview`].

use crate::doc::ObjectId;
use crate::math::DVec3;
use crate::styling::select::{CurveTool as TableTool, PatchPoint};
use crate::styling::{Attractor, ModelingFrame};

use crate::interact::input::{Hand, Pose};
use crate::interact::tools::ToolContext;

/// A plane held by the non-dominant hand (model space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawPlane {
    /// A point on it (the grip position).
    pub origin: DVec3,
    /// Unit normal (the hand's aim direction).
    pub normal: DVec3,
}

impl DrawPlane {
    pub(super) fn project(&self, p: DVec3) -> DVec3 {
        p - self.normal * (p - self.origin).dot(self.normal)
    }

    pub(super) fn mirror(&self, p: DVec3) -> DVec3 {
        crate::math::reflect(p, self.origin, self.normal)
    }
}

/// A patch is this much nearer to the tip than every curve (metres)
/// before a forced smooth, sharpen or pull acts on the surface.
pub const SURFACE_MARGIN: f64 = 0.01;

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

/// What a forced attract draws the curve towards: held by the other hand.
pub(super) fn attractor_of(cx: &ToolContext, pen: &Pen) -> Option<Attractor> {
    let (grip, aim) = (pen.grip?, pen.aim?);
    let to_model = cx.model.inverse();
    let a = to_model.apply(grip.position).to_array();
    let dir = to_model.apply_dir(aim.forward()).normalize_or_zero();
    if dir == DVec3::ZERO {
        return None;
    }
    Some(if pen.grab {
        Attractor::Plane {
            a,
            normal: dir.to_array(),
        }
    } else if pen.trigger {
        Attractor::Line {
            a,
            dir: dir.to_array(),
        }
    } else {
        Attractor::Point { p: a }
    })
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

/// One hand's controller this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Pen {
    pub(super) tracked: bool,
    pub(super) aim: Option<Pose>,
    pub(super) grip: Option<Pose>,
    pub(super) trigger: bool,
    pub(super) grab: bool,
    pub(super) primary: bool,
    pub(super) secondary: bool,
    pub(super) stick_x: f64,
    pub(super) teleported: bool,
}

pub(super) fn read_pen(cx: &ToolContext, hand: Hand) -> Pen {
    let Some(c) = cx.frame.controller(hand) else {
        return Pen::default();
    };
    let b = c.buttons.unwrap_or_default();
    Pen {
        tracked: c.aim.is_some() && c.buttons.is_some(),
        aim: c.aim,
        grip: c.grip,
        trigger: b.select > 0.5,
        grab: b.grab > 0.5,
        primary: b.primary,
        secondary: b.secondary,
        stick_x: b.stick[0],
        teleported: c.teleported,
    }
}

/// A held trigger.
#[derive(Clone, Debug)]
pub(super) struct Stroke {
    pub(super) mode: CurveMode,
    pub(super) target: Option<CurveTarget>,
    pub(super) patch: Option<PatchTarget>,
    /// A forced attract's attractor, taken at the press.
    pub(super) attractor: Option<Attractor>,
    pub(super) plane: Option<DrawPlane>,
    pub(super) symmetry: Option<DrawPlane>,
    /// Tip samples (model space).
    pub(super) path: Vec<DVec3>,
    /// The other hand's modeling frame at each sample (model space), when
    /// drawing in the held frame (paper 3 §5.4).
    pub(super) frames: Vec<ModelingFrame>,
    pub(super) lost_since: Option<f64>,
}
