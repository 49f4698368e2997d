//! The GC tool's state between frames: the Figure 10 state it is in and
//! the gesture each state carries (a drag, a pinch, a view grab, a hold).
//! What it shows, `GcPreview`, lives on the preview side.

use crate::gc::ShapeType;
use crate::math::DVec3;
use crate::sketch::{DrawnSection, SketchPlane};

use super::create::Start;
use super::GcTarget;
use crate::interact::gesture::bimanual::HandleBar;
use crate::interact::gesture::similarity::Similarity;
use crate::interact::input::{Hand, Pose};

#[derive(Clone, Debug)]
pub(super) enum State {
    Idle,
    Placed(Start),
    SketchSection(Start, Vec<DVec3>),
    Sectioned(Start, DrawnSection),
    SketchSpine(Start, DrawnSection, Vec<DVec3>),
    /// A key point or section picked by POINT, waiting for its stroke.
    ReplaceArmed(GcTarget, SketchPlane),
    Replace(GcTarget, SketchPlane, Vec<DVec3>),
    Drag(Drag),
    Pinch(PinchState),
    View(ViewGrab),
}

impl State {
    pub(super) fn name(&self) -> &'static str {
        match self {
            State::Idle => "idle",
            State::Placed(_) => "placed",
            State::SketchSection(..) => "sketch_section",
            State::Sectioned(..) => "sectioned",
            State::SketchSpine(..) => "sketch_spine",
            State::ReplaceArmed(..) => "replace",
            State::Replace(..) => "sketch_replace",
            State::Drag(_) => "drag",
            State::Pinch(_) => "pinch",
            State::View(_) => "view",
        }
    }
}

#[derive(Clone, Debug)]
pub(super) struct Drag {
    pub(super) target: GcTarget,
    /// Palm (world) where the drag started.
    pub(super) start: DVec3,
    pub(super) started: f64,
    /// The last good motion (model space).
    pub(super) motion: DVec3,
    /// Still eligible for the instance hold.
    pub(super) may_instance: bool,
}

#[derive(Clone, Debug)]
pub(super) struct PinchState {
    pub(super) target: GcTarget,
    /// (time, proposed shape), recent frames.
    pub(super) history: Vec<(f64, ShapeType)>,
}

#[derive(Clone, Debug)]
pub(super) struct ViewGrab {
    /// The view when the grab (or the last change of hands) started.
    pub(super) before: Similarity,
    pub(super) hands: Vec<(Hand, Pose)>,
    pub(super) bar: Option<HandleBar>,
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Hold {
    pub(super) target: GcTarget,
    pub(super) since: f64,
    pub(super) palm: DVec3,
    pub(super) fired: bool,
}
