//! What the curve tool works with: the pen, the stroke being drawn and
//! the attractor a forced attract pulls towards. What it shows (the
//! plane, the mode, the pointed curve or patch) lives on the preview
//! side, in `tools/preview/curve.rs`.

use crate::math::DVec3;
use crate::styling::{Attractor, ModelingFrame};

use super::{CurveMode, CurveTarget, DrawPlane, PatchTarget};
use crate::interact::input::{Hand, Pose};
use crate::interact::tools::ToolContext;

/// A patch is this much nearer to the tip than every curve (metres)
/// before a forced smooth, sharpen or pull acts on the surface.
pub const SURFACE_MARGIN: f64 = 0.01;

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
