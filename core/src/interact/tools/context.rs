//! What a tool is: the [`Tool`] trait and the [`ToolContext`] it sees each
//! frame, and the helpers every tool shares (applying a command, giving up a
//! lost gesture, naming an object in the palette).

use crate::doc::{Document, ObjectId, ScriptCommand};
use crate::math::DVec3;

use super::preview::Preview;
use crate::interact::gesture::similarity::Similarity;
use crate::interact::gesture::GestureState;
use crate::interact::input::{Frame, Pose};
use crate::interact::palette::{ChoiceGroup, Snap};

/// What a tool sees each frame.
pub struct ToolContext<'a> {
    /// The sanitized frame.
    pub frame: &'a Frame,
    /// Gesture of the left and right hand.
    pub gestures: &'a [GestureState; 2],
    /// The document (read-only).
    pub doc: &'a Document,
    /// Model-to-world placement of the document (stage space, metres).
    pub model: &'a Similarity,
    /// Snapping of drags (the palette's settings; off outside a modeler
    /// session).
    pub snap: Snap,
}

/// A tool: a state machine from frames to preview state and commands.
pub trait Tool {
    /// The tool's name.
    fn name(&self) -> &'static str;
    /// Consumes one sanitized frame. Returns a command when a gesture
    /// completed this frame (at most one per frame).
    fn update(&mut self, cx: &ToolContext) -> Option<ScriptCommand>;
    /// Drops any gesture in progress without a command (the document is
    /// untouched).
    fn cancel(&mut self);
    /// What to render now.
    fn preview(&self) -> &Preview;
    /// Whether the tool reads tracked hands (their gestures): then a hand
    /// the runtime does not track is made from its controller
    /// ([`crate::interact::controller_hand`]).
    fn uses_hands(&self) -> bool {
        false
    }
    /// Where the palette's axis mirror planes go through for this tool
    /// (document space): the object it works on. `None`: the centre of
    /// the document.
    fn mirror_centre(&self, doc: &Document) -> Option<DVec3> {
        let _ = doc;
        None
    }
    /// The choices the palette shows for this tool (shape type, component,
    /// brush, ...), each with its active option.
    fn choices(&self) -> Vec<ChoiceGroup> {
        Vec::new()
    }
    /// Picks `option` of choice group `group` (indices into
    /// [`Tool::choices`]). A choice that is a document setting (the SDF
    /// grid step) returns its op; out-of-range indices change nothing.
    fn choose(&mut self, doc: &Document, group: usize, option: usize) -> Option<ScriptCommand> {
        let _ = (doc, group, option);
        None
    }
}

impl ToolContext<'_> {
    /// The model-space motion of a hand whose grip went from `grip0` to
    /// `grip` (world poses), or `None` when it is degenerate (a drag then
    /// keeps its last motion).
    pub(crate) fn grip_motion(&self, grip0: &Pose, grip: &Pose) -> Option<Similarity> {
        let world = Similarity::from_pose(&grip.compose(&grip0.inverse()));
        Some(self.model.conjugate(&world)).filter(Similarity::is_valid)
    }
}

/// Lost tracking during a gesture: starts the clock at `now` if it is not
/// running and says whether the loss has lasted longer than `grace`
/// seconds (time to give the gesture up; until then the tool waits).
pub(crate) fn lost_too_long(lost_since: &mut Option<f64>, now: f64, grace: f64) -> bool {
    now - *lost_since.get_or_insert(now) > grace
}

// The tool registry: every tool a host or a trace can name, in one place.

/// How the palette names a document object: its name, else its kind and
/// id (`solid #3`).
pub(crate) fn object_label(id: ObjectId, obj: &crate::doc::Object) -> String {
    if obj.name.is_empty() {
        format!("{} #{}", obj.kind.name(), id.0)
    } else {
        obj.name.clone()
    }
}
