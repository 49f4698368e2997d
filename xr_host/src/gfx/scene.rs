//! What the headset draws each frame, as plain data: the document's mesh,
//! the drag preview, rays and sketches as line segments, and where the
//! model sits in the world. The interaction step fills it; the frame loop
//! reads it. No Vulkan here, so both sides use it without depending on
//! each other.

use std::sync::Arc;

use glam::Mat4;
use shapewright::doc::ObjectId;
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
    /// Each object's triangles in [`Scene::document`], in order: the id
    /// and the range of triangle indices.
    pub document_objects: Vec<(ObjectId, std::ops::Range<u32>)>,
    /// The object left out of the drawn document: the one being dragged,
    /// whose preview stands in for it (so the two never overlap on
    /// screen, and hiding it costs no mesh work).
    pub hidden: Option<ObjectId>,
    /// World (the session's floor-level base space) from model.
    pub model_to_world: Mat4,
    /// The drag preview: the dragged object's mesh or the GC part as the
    /// gesture would leave it (model space, normals set).
    pub preview: Option<Arc<TriMesh>>,
    /// Applied to [`Scene::preview`] before `model_to_world`: the drag's
    /// motion (identity for a GC part).
    pub preview_motion: Mat4,
    /// Bumped whenever [`Scene::preview`] is another mesh (re-upload then;
    /// a drag that only moves keeps it).
    pub preview_version: u64,
    /// Rays and the sketch in progress (world space), as segment pairs.
    pub lines: Vec<LineVertex>,
    /// Flat triangles (world space): the palette, its labels, the active
    /// tool next to the hand, readouts and messages.
    pub ui: Vec<LineVertex>,
}

impl Scene {
    /// The vertices of the drawn document mesh to leave out (three per
    /// triangle, as the renderer expands them): the hidden object's.
    pub fn hidden_vertices(&self) -> Option<(u32, u32)> {
        let id = self.hidden?;
        let (_, r) = self.document_objects.iter().find(|(o, _)| *o == id)?;
        Some((r.start * 3, r.end * 3))
    }
}
