//! What the headset draws each frame, as plain data: the document's mesh,
//! the drag preview, rays and sketches as line segments, and where the
//! model sits in the world. The interaction step fills it; the frame loop
//! reads it. No Vulkan here, so both sides use it without depending on
//! each other.

use std::sync::Arc;

use glam::Mat4;
use shapewright::mesh::TriMesh;

use super::LineVertex;

/// What the renderer draws for the document and the active tool.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Bumped whenever [`Scene::document`] changes (re-upload then).
    pub version: u64,
    /// All objects of the document in one mesh (model space, normals set);
    /// None when the document is empty.
    pub document: Option<Arc<TriMesh>>,
    /// World (the session's floor-level base space) from model.
    pub model_to_world: Mat4,
    /// The object being dragged, where it would land (model space).
    pub preview: Option<Arc<TriMesh>>,
    /// Rays and the sketch in progress (world space), as segment pairs.
    pub lines: Vec<LineVertex>,
    /// Flat triangles (world space): the palette, its labels, the active
    /// tool next to the hand, readouts and messages.
    pub ui: Vec<LineVertex>,
}
