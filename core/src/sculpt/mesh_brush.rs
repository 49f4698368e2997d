//! Grid brushes generated from any closed mesh (paper 4 §4.2, "the brush
//! generator"), including the model being sculpted.
//!
//! The distance field comes from the shared mesh-to-SDF code of `core::sdf`
//! ([`crate::sdf::mesh_sdf::mesh_to_sdf`]: parry3d closest point,
//! pseudo-normal sign), so a brush is refused exactly when that code refuses
//! the mesh: open, non-manifold or inconsistently oriented meshes get
//! [`SculptError::NotClosedManifold`] and nothing changes.
//!
//! Choices:
//! - **What the op carries.** A [`MeshBrush`] names its mesh either inline
//!   ([`MeshSource::Mesh`]) or by object id ([`MeshSource::Object`]). An id
//!   means "that object's mesh at this point of the log": the stroke op
//!   resolves it when it is applied, so replaying the same log reproduces
//!   the same brush (ops before it rebuild the same mesh, bit for bit), and
//!   the log stays small when the brush is a large model. The id may be the
//!   sculpted object itself: its mesh before the stroke is used.
//! - **Frame.** The mesh is used in its own (for objects: world) units,
//!   re-centred on its bounding-box centre, which becomes the brush origin;
//!   the stroke's `brush_scale` scales it like any other brush.
//! - **Grid.** Spacing `step` and `padding` around the mesh's box are
//!   explicit parameters; the grid may hold at most [`MAX_BRUSH_SAMPLES`]
//!   samples ([`SculptError::BrushTooLarge`] otherwise). Values are the `f32`
//!   distances of `mesh_to_sdf`, widened to `f64`.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::brush::{check_finite, positive, BrushExtent, DistanceGrid};
use super::SculptError;
use crate::id::ObjectId;
use crate::mesh::TriMesh;
use crate::sdf::mesh_sdf::mesh_to_sdf;
use crate::sdf::SdfError;

/// Most samples a mesh brush's grid may have (2 Mi, 16 MiB of `f64`).
pub const MAX_BRUSH_SAMPLES: u64 = 1 << 21;

/// Where a mesh brush's mesh comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MeshSource {
    /// A mesh given inline (closed, counter-clockwise from outside).
    Mesh {
        /// Vertex positions.
        positions: Vec<[f64; 3]>,
        /// Triangles.
        triangles: Vec<[u32; 3]>,
    },
    /// The current mesh of a document object (any kind, the sculpted
    /// object included) at the point of the log where the stroke applies.
    Object {
        /// The object.
        id: ObjectId,
    },
}

/// A brush whose distance field is generated from a closed mesh.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MeshBrush {
    /// The mesh.
    pub source: MeshSource,
    /// Grid spacing, in the mesh's units.
    pub step: f64,
    /// Margin sampled around the mesh's box (at least 0).
    pub padding: f64,
}

impl MeshBrush {
    /// Checks the parameters that need no document: step, padding, inline
    /// positions finite.
    pub fn validate(&self) -> Result<(), SculptError> {
        positive("brush.step", self.step)?;
        check_finite("brush.padding", &[self.padding])?;
        if self.padding < 0.0 {
            return Err(SculptError::OutOfRange {
                field: "brush.padding".into(),
                value: self.padding,
                range: ">= 0",
            });
        }
        if let MeshSource::Mesh { positions, .. } = &self.source {
            for (i, p) in positions.iter().enumerate() {
                check_finite(&format!("brush.positions[{i}]"), p)?;
            }
        }
        Ok(())
    }

    /// The object the brush's mesh comes from, if any.
    pub fn object(&self) -> Option<ObjectId> {
        match &self.source {
            MeshSource::Object { id } => Some(*id),
            MeshSource::Mesh { .. } => None,
        }
    }

    /// The brush's distance grid, from the inline mesh or `object_mesh`
    /// (the current mesh of [`Self::object`], resolved by the document).
    pub fn to_grid(&self, object_mesh: Option<&TriMesh>) -> Result<DistanceGrid, SculptError> {
        self.validate()?;
        grid_from_mesh(self.mesh(object_mesh)?, self.step, self.padding)
    }

    /// What the brush will be, from its mesh alone, before its grid is
    /// sampled (for the stroke's time estimate, [`super::budget`]): the
    /// grid's sample count and the brush's extent (its size: the farthest
    /// vertex from the box centre the grid is centred on; its bound one
    /// grid cell diagonal more). Refuses what [`Self::to_grid`] would
    /// refuse for its size.
    pub fn plan(&self, object_mesh: Option<&TriMesh>) -> Result<(u64, BrushExtent), SculptError> {
        self.validate()?;
        let mesh = self.mesh(object_mesh)?;
        let (lo, hi) = mesh.bbox().ok_or_else(|| SculptError::NotClosedManifold {
            what: "brush",
            problems: "empty".into(),
        })?;
        let samples = grid_samples(lo, hi, self.step, self.padding)?;
        let c = (lo + hi) * 0.5;
        let size = mesh
            .positions
            .iter()
            .map(|p| DVec3::from_array(*p).distance(c))
            .fold(0.0, f64::max);
        Ok((
            samples,
            BrushExtent {
                size,
                bound: size + self.step * 3f64.sqrt(),
            },
        ))
    }

    /// The inline mesh, or `object_mesh`.
    fn mesh(&self, object_mesh: Option<&TriMesh>) -> Result<TriMesh, SculptError> {
        Ok(match &self.source {
            MeshSource::Mesh {
                positions,
                triangles,
            } => TriMesh::new(positions.clone(), triangles.clone()),
            MeshSource::Object { id } => object_mesh
                .ok_or_else(|| SculptError::Invalid(format!("the mesh of object {id} is missing")))?
                .clone(),
        })
    }
}

/// The samples of the grid over the box `lo..hi` padded by `padding` at
/// spacing `step`, or [`SculptError::BrushTooLarge`].
fn grid_samples(lo: DVec3, hi: DVec3, step: f64, padding: f64) -> Result<u64, SculptError> {
    let n = ((hi - lo + DVec3::splat(2.0 * padding)) / step).ceil() + DVec3::ONE;
    let samples = n.x * n.y * n.z;
    if samples.is_nan() || samples > MAX_BRUSH_SAMPLES as f64 {
        return Err(SculptError::BrushTooLarge {
            samples: if samples.is_finite() {
                samples as u64
            } else {
                u64::MAX
            },
            limit: MAX_BRUSH_SAMPLES,
        });
    }
    Ok(samples as u64)
}

/// The distance grid of `mesh` re-centred on its box centre.
pub fn grid_from_mesh(
    mut mesh: TriMesh,
    step: f64,
    padding: f64,
) -> Result<DistanceGrid, SculptError> {
    let not_closed = |problems: String| SculptError::NotClosedManifold {
        what: "brush",
        problems,
    };
    let (lo, hi) = mesh.bbox().ok_or_else(|| not_closed("empty".into()))?;
    grid_samples(lo, hi, step, padding)?;
    let c = (lo + hi) * 0.5;
    for p in &mut mesh.positions {
        *p = (DVec3::from_array(*p) - c).to_array();
    }
    let sdf = mesh_to_sdf(&mesh, step, padding).map_err(|e| match e {
        SdfError::BadMesh(p) => not_closed(p),
        other => not_closed(other.to_string()),
    })?;
    Ok(DistanceGrid {
        origin: sdf.origin,
        step: sdf.step,
        dims: sdf.dims.map(|d| d as u32),
        values: sdf.values.iter().map(|&v| v as f64).collect(),
    })
}
