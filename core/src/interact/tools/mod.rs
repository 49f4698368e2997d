//! The tool framework: a [`Tool`] is a state machine that consumes
//! sanitized frames and produces preview state every frame and, when a
//! gesture completes, exactly one command (an op, undo or redo) — never one
//! per frame.
//!
//! Tools see the document read-only through a [`ToolContext`]; the
//! [`crate::interact::Session`] applies their commands to the log. Commands are the
//! doc module's [`ScriptCommand`], so a session's output is an op script.

pub(crate) mod brush_tool;
pub(crate) mod csg_tool;
#[cfg(test)]
mod ctl_tool_tests;
pub(crate) mod curve_tool;
#[cfg(test)]
pub(crate) mod curve_tool_tests;
pub(crate) mod gc_tool;
pub(crate) mod object_tool;
pub(crate) mod pick;
#[cfg(test)]
mod tool_tests;

use std::sync::Arc;

use crate::doc::{Document, LogError, ObjectId, OpLog, ScriptCommand};
use crate::math::{DAffine3, DVec3, Transform};
use crate::mesh::TriMesh;
use crate::solid::SolidShape;

use crate::interact::gesture::similarity::Similarity;
use crate::interact::gesture::GestureState;
use crate::interact::input::Frame;
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

/// A ray to draw (world space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreviewRay {
    /// Origin.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
    /// Length to draw: to the hit, or the tool's reach.
    pub length: f64,
    /// The ray hits an object.
    pub hit: bool,
}

/// An object shown somewhere else than the document has it (during a
/// drag).
#[derive(Clone, Debug, PartialEq)]
pub struct MovingPreview {
    /// The object.
    pub id: ObjectId,
    /// Its placement if the gesture ended now.
    pub transform: Transform,
    /// The model-space motion from its document placement.
    pub motion: Similarity,
}

/// What to render for the tool this frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Preview {
    /// Rays of the left and right hand.
    pub rays: [Option<PreviewRay>; 2],
    /// The object under a ray.
    pub highlighted: Option<ObjectId>,
    /// The selected object.
    pub selected: Option<ObjectId>,
    /// The object being dragged.
    pub moving: Option<MovingPreview>,
    /// The sketch in progress (model space), for sketching tools.
    pub sketch: Vec<DVec3>,
    /// The model placement the tool shows the document with (model to
    /// stage), when the tool moves the view (the sculpt tool's orienting
    /// hand); `None`: the session's placement.
    pub view: Option<Similarity>,
    /// The tool's current choices, for a status line (e.g. the CSG tool's
    /// SceneOperate operation, menu component and scale axis).
    pub mode: String,
    /// A live readout of the drag in progress (distance, angle, scale and
    /// what it snapped to); empty when nothing is dragged.
    pub readout: String,
    /// What only the active tool shows.
    pub tool: ToolPreview,
}

/// The part of a [`Preview`] only one tool has: hosts match on it.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ToolPreview {
    /// Nothing tool-specific.
    #[default]
    None,
    /// The object tool: the shape the next placement will create.
    Placing(Option<SolidShape>),
    /// The CSG tool's pending operands.
    Csg(CsgPreview),
    /// The curve tool: selected tool, pointed curve point, planes.
    Curve(crate::interact::tools::curve_tool::CurvePreview),
    /// The sculpt brush (world space), while a controller holds it.
    Brush(Option<BrushPreview>),
    /// The generalized-cylinder tool's state.
    Gc(crate::interact::tools::gc_tool::GcPreview),
}

/// The CSG tool's pending SDF operands to show.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CsgPreview {
    /// The pending SDF operand under a ray (index in the tool's volume).
    pub highlighted_operand: Option<usize>,
    /// The selected pending SDF operand.
    pub selected_operand: Option<usize>,
    /// The SDF operand being dragged or scaled, where it would go now.
    pub moving_operand: Option<OperandPreview>,
}

/// A pending SDF operand shown at a placement the document does not have
/// yet (during a drag or a two-hand scale).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OperandPreview {
    /// The SDF volume.
    pub volume: ObjectId,
    /// Index among its pending operands.
    pub index: usize,
    /// Its placement if the gesture ended now (model space).
    pub transform: Transform,
}

/// The sculpt brush to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrushPreview {
    /// Centre (world space).
    pub position: DVec3,
    /// Bounding radius (world space).
    pub radius: f64,
    /// Pressure now (trigger value).
    pub pressure: f64,
    /// A stroke is in progress.
    pub stroking: bool,
}

/// Accessors of one variant: `x()` reads it if the tool shows it, `x_mut()`
/// makes it the tool's variant (keeping it if it already is).
macro_rules! tool_preview {
    ($get:ident, $get_mut:ident, $variant:ident, $t:ty) => {
        #[doc = concat!("The `", stringify!($variant), "` part, if the tool shows it.")]
        pub fn $get(&self) -> Option<&$t> {
            match &self.tool {
                ToolPreview::$variant(x) => Some(x),
                _ => None,
            }
        }
        #[doc = concat!("The `", stringify!($variant), "` part, made the tool's if it was not.")]
        pub fn $get_mut(&mut self) -> &mut $t {
            if !matches!(self.tool, ToolPreview::$variant(_)) {
                self.tool = ToolPreview::$variant(Default::default());
            }
            match &mut self.tool {
                ToolPreview::$variant(x) => x,
                _ => unreachable!("set just above"),
            }
        }
    };
}

impl Preview {
    tool_preview!(placing, placing_mut, Placing, Option<SolidShape>);
    tool_preview!(csg, csg_mut, Csg, CsgPreview);
    tool_preview!(
        curve,
        curve_mut,
        Curve,
        crate::interact::tools::curve_tool::CurvePreview
    );
    tool_preview!(brush, brush_mut, Brush, Option<BrushPreview>);
    tool_preview!(gc, gc_mut, Gc, crate::interact::tools::gc_tool::GcPreview);

    /// The mesh to draw for the object being dragged (model space), its
    /// document mesh moved by the drag: by the motion, or, when the new
    /// placement is not the motion after the old one (a per-axis scale),
    /// from the old placement to the new one.
    pub fn preview_mesh(&self, doc: &Document) -> Option<Arc<TriMesh>> {
        let (mesh, a) = self.preview_motion(doc)?;
        let mut mesh = Arc::unwrap_or_clone(mesh);
        mesh.transform(&a);
        Some(Arc::new(mesh))
    }

    /// The object being dragged, as its document mesh (shared, not
    /// copied) and the affine map that takes it to where it would land:
    /// what [`Preview::preview_mesh`] applies. A renderer draws the mesh
    /// with the map as its model matrix, so a drag costs no mesh work per
    /// frame.
    pub fn preview_motion(&self, doc: &Document) -> Option<(Arc<TriMesh>, DAffine3)> {
        let m = self.moving.as_ref()?;
        let obj = doc.get(m.id).ok()?;
        let base = obj.transform();
        let by_motion = m.motion.then_transform(&base).scale == m.transform.scale;
        let a = if by_motion {
            m.motion.to_affine()
        } else {
            m.transform.to_affine().ok()? * base.to_affine().ok()?.inverse()
        };
        Some((Arc::clone(&obj.mesh), a))
    }
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
    /// ([`crate::interact::gesture::controller_hand`]).
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

/// Lost tracking during a gesture: starts the clock at `now` if it is not
/// running and says whether the loss has lasted longer than `grace`
/// seconds (time to give the gesture up; until then the tool waits).
pub(crate) fn lost_too_long(lost_since: &mut Option<f64>, now: f64, grace: f64) -> bool {
    now - *lost_since.get_or_insert(now) > grace
}

/// Applies a command to the log.
pub fn apply_command(log: &mut OpLog, cmd: &ScriptCommand) -> Result<(), LogError> {
    match cmd {
        ScriptCommand::Op(op) => log.apply(op.clone()).map(|_| ()),
        ScriptCommand::Undo => log.undo(),
        ScriptCommand::Redo => log.redo(),
    }
}

// The tool registry: every tool a host or a trace can name, in one place.

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

/// How the palette names a document object: its name, else its kind and
/// id (`solid #3`).
pub(crate) fn object_label(id: ObjectId, obj: &crate::doc::Object) -> String {
    if obj.name.is_empty() {
        format!("{} #{}", obj.kind.name(), id.0)
    } else {
        obj.name.clone()
    }
}
