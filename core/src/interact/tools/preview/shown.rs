//! [`Preview`]: what a tool shows each frame (rays, the moving object, the
//! sketch) and its tool-specific part ([`ToolPreview`]).

use std::sync::Arc;

use crate::doc::{Document, ObjectId};
use crate::math::{DAffine3, DVec3, Transform};
use crate::mesh::TriMesh;
use crate::solid::SolidShape;

use super::{CurvePreview, GcPreview};
use crate::interact::gesture::similarity::Similarity;

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
    Curve(CurvePreview),
    /// The sculpt brush (world space), while a controller holds it.
    Brush(Option<BrushPreview>),
    /// The generalized-cylinder tool's state.
    Gc(GcPreview),
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
    tool_preview!(curve, curve_mut, Curve, CurvePreview);
    tool_preview!(brush, brush_mut, Brush, Option<BrushPreview>);
    tool_preview!(gc, gc_mut, Gc, GcPreview);

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
