//! The changed-region API: a surface under sculpting as slot-indexed flat
//! render buffers, brought up to date each frame in time proportional to
//! what the frame changed (paper §5.2 renders the split-edge mesh directly;
//! we keep its slots so a renderer never re-walks the whole surface).
//!
//! Slots are the half-edge mesh's own ids: vertex `v` is at
//! `positions[v]` / `normals[v]`, face `f` at `triangles[f]`. Removed faces
//! become `[0, 0, 0]` (zero area: rasterizers draw nothing); removed
//! vertices keep stale values that no live triangle refers to. Slots are
//! reused LIFO by the mesh, so buffers grow only when the mesh's capacity
//! does.
//!
//! How a host uses it (the OpenXR host's renderer, Blender's draw handler):
//! 1. Once per sculpt object (on load, and after anything other than the
//!    live stroke changed the surface: undo, redo, another op) build
//!    [`RenderBuffers::from_mesh`] from the sculptor's mesh and upload the
//!    three arrays whole (O(mesh), never per frame). Keep the
//!    [`super::Sculptor`] alive between strokes; `begin_stroke` is O(1).
//! 2. Each frame, after [`super::Sculptor::apply_frame`] (any number of
//!    them), call [`super::Sculptor::sync_render`]: it rewrites only the
//!    slots whose position, normal or corners changed and returns them as
//!    sorted, merged [`DirtySlots`] ranges; upload just those ranges
//!    (mapped memcpy or `vkCmdUpdateBuffer` per range). When the arrays
//!    grew (`capacity_grew`), reallocate the GPU buffers first (keep
//!    headroom, e.g. 1.25x, so that is rare).
//! 3. Draw `triangles` as an indexed triangle list over the whole slot
//!    range; no compaction is needed.
//!
//! Normals are area-weighted sums of the face normals around each vertex
//! (cheaper than the angle-weighted ones of [`crate::mesh::TriMesh`], and
//! what a renderer needs), summed around the vertex's fan in the mesh's
//! order, so an incrementally updated buffer is bit-identical to one built
//! from scratch (tested).

use std::ops::Range;

use glam::DVec3;

use super::halfedge::{FaceId, HalfEdgeMesh, VertId};
use super::par::sort_by_u32;

/// Slot-indexed render buffers of a half-edge surface (f32, flat arrays
/// that go to Vulkan, numpy or Blender without conversion loops).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderBuffers {
    /// Position per vertex slot.
    pub positions: Vec<[f32; 3]>,
    /// Unit normal per vertex slot.
    pub normals: Vec<[f32; 3]>,
    /// Corners per face slot, counter-clockwise from outside; `[0, 0, 0]`
    /// for a removed face.
    pub triangles: Vec<[u32; 3]>,
}

/// Slot ranges rewritten by one [`super::Sculptor::sync_render`]: sorted,
/// disjoint, not adjacent (touching ranges are merged).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DirtySlots {
    /// Vertex slots whose position or normal changed.
    pub vertices: Vec<Range<u32>>,
    /// Face slots whose corners changed.
    pub triangles: Vec<Range<u32>>,
    /// The arrays grew since the last sync (reallocate GPU buffers).
    pub capacity_grew: bool,
}

impl DirtySlots {
    /// Number of vertex slots to upload.
    pub fn vertex_count(&self) -> usize {
        self.vertices.iter().map(|r| r.len()).sum()
    }
    /// Number of face slots to upload.
    pub fn triangle_count(&self) -> usize {
        self.triangles.iter().map(|r| r.len()).sum()
    }
}

/// The area-weighted normal of live vertex `v`, summed around its fan.
#[inline]
pub fn vertex_normal(m: &HalfEdgeMesh, v: VertId) -> DVec3 {
    let mut n = DVec3::ZERO;
    m.for_each_out(v, |h| n += m.face_area_vec(h.face()));
    n.normalize_or(DVec3::Z)
}

#[inline]
fn f32x3(p: DVec3) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
}

#[inline]
fn corners(m: &HalfEdgeMesh, f: FaceId) -> [u32; 3] {
    if m.face_alive(f) {
        m.face_verts(f).map(|v| v.0)
    } else {
        [0; 3]
    }
}

impl RenderBuffers {
    /// Buffers for the whole surface (O(mesh): once per object, not per
    /// frame).
    pub fn from_mesh(m: &HalfEdgeMesh) -> Self {
        let nv = m.vertex_capacity() as usize;
        let mut out = Self {
            positions: vec![[0.0; 3]; nv],
            normals: vec![[0.0, 0.0, 1.0]; nv],
            triangles: (0..m.face_capacity())
                .map(|f| corners(m, FaceId(f)))
                .collect(),
        };
        for v in m.vertices() {
            out.positions[v.0 as usize] = f32x3(m.position(v));
            out.normals[v.0 as usize] = f32x3(vertex_normal(m, v));
        }
        out
    }

    /// Grows the arrays to the mesh's capacities; true when they grew.
    pub(crate) fn fit(&mut self, m: &HalfEdgeMesh) -> bool {
        let (nv, nf) = (m.vertex_capacity() as usize, m.face_capacity() as usize);
        let grew = self.positions.len() < nv || self.triangles.len() < nf;
        if self.positions.len() < nv {
            self.positions.resize(nv, [0.0; 3]);
            self.normals.resize(nv, [0.0, 0.0, 1.0]);
        }
        if self.triangles.len() < nf {
            self.triangles.resize(nf, [0; 3]);
        }
        grew
    }

    /// Rewrites vertex slot `v` (position and normal) from the mesh.
    #[inline]
    pub(crate) fn write_vertex(&mut self, m: &HalfEdgeMesh, v: VertId, normal: DVec3) {
        self.positions[v.0 as usize] = f32x3(m.position(v));
        self.normals[v.0 as usize] = f32x3(normal);
    }

    /// Rewrites face slot `f` from the mesh.
    #[inline]
    pub(crate) fn write_face(&mut self, m: &HalfEdgeMesh, f: FaceId) {
        self.triangles[f.0 as usize] = corners(m, f);
    }
}

/// Sorts `ids`, drops repeats and merges them into ranges of consecutive
/// slots.
pub(crate) fn to_ranges(ids: &mut Vec<u32>, scratch: &mut Vec<u32>) -> Vec<Range<u32>> {
    sort_by_u32(ids, scratch, |&i| i);
    ids.dedup();
    let mut out: Vec<Range<u32>> = Vec::new();
    for &i in ids.iter() {
        match out.last_mut() {
            Some(r) if r.end == i => r.end = i + 1,
            _ => out.push(i..i + 1),
        }
    }
    out
}
