//! 3D warp brushes on an adaptive half-edge mesh
//! (papers/warp-brush-adaptive-mesh.txt §4–6, SPEC.md §4).
//!
//! - [`halfedge`]: the split-edge mesh (§5.1), conversion from/to
//!   [`crate::mesh::TriMesh`] (closed meshes only), validity checker.
//! - [`adapt`]: longest-edge bisection and shortest-edge collapse (§5.3).
//! - [`brush`]: brushes as distance fields with gradients (§4.2, §4.5).
//! - [`warp`]: weight functions (§4.3) and warp operators (§4.4).
//! - [`grid`]: a uniform hash grid of vertices, updated incrementally.
//! - [`stroke`]: strokes applied frame by frame by a [`Sculptor`] (§4.1).
//! - [`base`]: base meshes (geodesic sphere, box, slab).
//! - [`ops`]: the `sculpt_mesh` object kind and the `sculpt_create` and
//!   `sculpt_stroke` ops.
//!
//! Own code rather than a crate: the per-frame hot path needs a layout we
//! control (implicit `next`/face, 8 bytes per half-edge, free lists reused
//! deterministically for bit-identical replay) and the specific
//! conforming-bisection and link-condition collapse of the paper; mesh
//! crates were not evaluated in depth for this.

pub mod adapt;
pub mod base;
pub mod brush;
mod error;
pub mod grid;
pub mod halfedge;
pub mod ops;
pub mod stroke;
pub mod warp;

pub use brush::{BrushPose, BrushShape, DistanceGrid};
pub use error::SculptError;
pub use halfedge::{FaceId, HalfEdgeId, HalfEdgeMesh, VertId};
pub use ops::{SculptBase, SculptCreate, SculptMesh, SculptStroke};
pub use stroke::{FrameInput, FrameStats, Sculptor, StrokeSample, StrokeSettings};
pub use warp::{Falloff, Warp};

#[cfg(test)]
mod tests;
