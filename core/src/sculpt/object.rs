//! The sculpt object kind and its ops' payloads: `sculpt_create` makes a
//! [`SculptMesh`] from a base shape or any closed mesh; `sculpt_stroke`
//! applies one whole stroke (its sampled path is stored in the op, so
//! undo, redo and replay reproduce it bit for bit).
//!
//! A base or brush made from "another object's mesh" names it by
//! [`ObjectId`]; the document resolves that mesh and hands it in
//! (`object_mesh` below), so nothing here looks objects up.

use glam::{DQuat, DVec3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::base::{geodesic_sphere, grid_box, sphere_frequency};
use super::brush::{check_finite, positive, BrushPose, BrushShape};
use super::budget::{estimate_strokes, CreateCost, StrokeCost};
use super::halfedge::HalfEdgeMesh;
use super::stroke::{estimate_on, run_costed, Sculptor, StrokeSample, StrokeSettings};
use super::SculptError;
use crate::id::ObjectId;
use crate::math::{MirrorPlane, Transform};
use crate::mesh::TriMesh;

/// A sculpted surface placed by a transform (uniform scale: the model's
/// scale, separate from the brush's).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SculptMesh {
    /// The surface in model space.
    pub surface: HalfEdgeMesh,
    /// Placement (translation, rotation, uniform positive scale).
    pub transform: Transform,
}

impl SculptMesh {
    /// The surface as a triangle mesh in world space.
    pub fn evaluate(&self) -> Result<TriMesh, SculptError> {
        let affine = self
            .transform
            .to_affine()
            .map_err(|e| SculptError::Invalid(e.to_string()))?;
        let mut m = self.surface.to_trimesh();
        m.transform(&affine);
        Ok(m)
    }
}

/// What to start sculpting from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum SculptBase {
    /// A geodesic sphere centred on the origin.
    Sphere {
        /// Radius.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        radius: f64,
        /// Target edge length.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        edge_length: f64,
    },
    /// A box centred on the origin.
    Box {
        /// Full sizes along x, y, z.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        size: [f64; 3],
        /// Target edge length.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        edge_length: f64,
    },
    /// A thin box in the xy plane.
    Slab {
        /// Full sizes along x and y.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        size: [f64; 2],
        /// Thickness along z.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        thickness: f64,
        /// Target edge length.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        edge_length: f64,
    },
    /// The current mesh of another document object (any kind), which must
    /// be closed.
    Object {
        /// The object.
        id: ObjectId,
    },
    /// An imported closed mesh.
    Mesh {
        /// Vertex positions.
        #[schemars(extend("x-unit" = "m"))]
        positions: Vec<[f64; 3]>,
        /// Triangles, counter-clockwise from outside.
        triangles: Vec<[u32; 3]>,
    },
}

/// `sculpt_create`: a new sculpt object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SculptCreate {
    /// The base shape.
    pub base: SculptBase,
    /// Placement; its scale must be uniform and positive.
    #[serde(default)]
    pub transform: Transform,
}

/// `sculpt_stroke`: one stroke on a sculpt object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SculptStroke {
    /// Brush, warp, weights and resolution settings.
    pub settings: StrokeSettings,
    /// The sampled path, in world space.
    pub samples: Vec<StrokeSample>,
    /// Mirror symmetry: a second brush follows the path's mirror image
    /// across this plane (document space), frame by frame with the first
    /// ([`crate::math::MirrorPlane`]). Absent: no mirror.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mirror: Option<Box<MirrorPlane>>,
}

/// The uniform positive scale of a sculpt's placement, or a typed error.
pub fn model_scale(t: &Transform) -> Result<f64, SculptError> {
    let [a, b, c] = t.scale;
    if a != b || b != c || a.is_nan() || a <= 0.0 {
        return Err(SculptError::NonUniformScale(t.scale));
    }
    Ok(a)
}

impl SculptBase {
    /// The object whose mesh this base is made from, if any (the document
    /// resolves it and passes the mesh to [`SculptCreate::build`]).
    pub fn object(&self) -> Option<ObjectId> {
        match self {
            Self::Object { id } => Some(*id),
            _ => None,
        }
    }
}

impl SculptCreate {
    /// The new sculpt object; `object_mesh` is the mesh of
    /// [`SculptBase::object`] when the base is another object.
    pub fn build(&self, object_mesh: Option<&TriMesh>) -> Result<SculptMesh, SculptError> {
        self.transform
            .validate()
            .map_err(|e| SculptError::Invalid(e.to_string()))?;
        model_scale(&self.transform)?;
        let mesh = match &self.base {
            SculptBase::Sphere {
                radius,
                edge_length,
            } => geodesic_sphere(*radius, sphere_frequency(*radius, *edge_length)?),
            SculptBase::Box { size, edge_length } => grid_box(*size, *edge_length)?,
            SculptBase::Slab {
                size,
                thickness,
                edge_length,
            } => grid_box([size[0], size[1], *thickness], *edge_length)?,
            SculptBase::Object { id } => object_mesh
                .ok_or_else(|| SculptError::Invalid(format!("the mesh of object {id} is missing")))?
                .clone(),
            SculptBase::Mesh {
                positions,
                triangles,
            } => {
                for (i, p) in positions.iter().enumerate() {
                    check_finite(&format!("base.positions[{i}]"), p)?;
                }
                TriMesh::new(positions.clone(), triangles.clone())
            }
        };
        CreateCost {
            vertices: mesh.positions.len() as f64,
        }
        .check("base")?;
        let surface = HalfEdgeMesh::from_trimesh(&mesh, "base")?;
        Ok(SculptMesh {
            surface,
            transform: self.transform,
        })
    }
}

/// Validates a stroke and converts its samples to model-space poses.
pub fn stroke_poses(
    transform: &Transform,
    settings: &StrokeSettings,
    samples: &[StrokeSample],
) -> Result<(f64, Vec<(BrushPose, f64)>), SculptError> {
    settings.validate()?;
    if samples.is_empty() {
        return Err(SculptError::EmptyStroke);
    }
    for (i, s) in samples.iter().enumerate() {
        s.validate(i)?;
    }
    let scale = model_scale(transform)?;
    positive("transform.scale", scale)?;
    let t = DVec3::from_array(transform.translate);
    let r_inv = DQuat::from_array(transform.rotate).normalize().inverse();
    let poses = samples
        .iter()
        .map(|s| {
            let p = r_inv * (DVec3::from_array(s.position) - t) / scale;
            let q = (r_inv * DQuat::from_array(s.rotation).normalize()).normalize();
            (
                BrushPose {
                    position: p,
                    rotation: q,
                    scale: settings.brush_scale / scale,
                },
                s.pressure,
            )
        })
        .collect();
    Ok((scale, poses))
}

impl SculptStroke {
    /// The object whose mesh the stroke's brush is made from, if any (the
    /// document resolves it and passes the mesh to [`Self::apply_to`]).
    pub fn brush_object(&self) -> Option<ObjectId> {
        match &self.settings.brush {
            BrushShape::Mesh(m) => m.object(),
            _ => None,
        }
    }

    /// What the stroke will cost on `target` (see [`Self::apply_to`]): the
    /// estimate the op checks against the time budget, or the refusal.
    pub fn estimate(
        &self,
        target: &SculptMesh,
        brush_mesh: Option<&TriMesh>,
    ) -> Result<StrokeCost, SculptError> {
        Ok(self.prepare(target, brush_mesh)?.cost)
    }

    /// Runs the stroke on `target`; `brush_mesh` is the mesh of
    /// [`Self::brush_object`] (before this stroke) when the brush is made
    /// from an object.
    ///
    /// The time budget is checked before any work on the meshes (the
    /// frames, the mesh's size and the brush grid's samples, with the
    /// brush's size from its mesh), again with the mesh's density once it
    /// is indexed (a copy and a hash grid: part of the first estimate),
    /// and only then is a mesh brush's grid sampled and the stroke run
    /// ([`super::budget`]).
    pub fn apply_to(
        &self,
        target: &mut SculptMesh,
        brush_mesh: Option<&TriMesh>,
    ) -> Result<(), SculptError> {
        let Prepared {
            mut sculptor,
            cost,
            scale,
            poses,
            mirrored,
        } = self.prepare(target, brush_mesh)?;
        let mut paths = vec![poses.as_slice()];
        paths.extend(mirrored.as_deref());
        // A mesh brush becomes a grid here, from the document as it is
        // before this stroke (so replay rebuilds the same brush).
        let resolved;
        let settings = match &self.settings.brush {
            BrushShape::Mesh(m) => {
                resolved = StrokeSettings {
                    brush: BrushShape::Grid(m.to_grid(brush_mesh)?),
                    ..self.settings.clone()
                };
                &resolved
            }
            _ => &self.settings,
        };
        let extent = settings.brush.extent();
        run_costed(
            &mut sculptor,
            &settings.brush,
            extent,
            settings,
            scale,
            &paths,
            &cost,
        )?;
        target.surface = sculptor.into_mesh();
        Ok(())
    }

    /// Validates, estimates and checks the stroke, and indexes the mesh.
    fn prepare(
        &self,
        target: &SculptMesh,
        brush_mesh: Option<&TriMesh>,
    ) -> Result<Prepared, SculptError> {
        let (scale, poses) = stroke_poses(&target.transform, &self.settings, &self.samples)?;
        let mirrored = match &self.mirror {
            Some(m) => {
                m.validate()?;
                let samples: Vec<StrokeSample> =
                    self.samples.iter().map(|s| s.mirrored(m)).collect();
                Some(stroke_poses(&target.transform, &self.settings, &samples)?.1)
            }
            None => None,
        };
        let mut paths = vec![poses.as_slice()];
        paths.extend(mirrored.as_deref());
        let (grid_samples, extent) = match &self.settings.brush {
            BrushShape::Mesh(m) => m.plan(brush_mesh)?,
            b => (0, b.extent()),
        };
        let mut cost = estimate_strokes(&self.settings, extent, scale, &paths, None)?;
        cost.faces = target.surface.face_count() as f64;
        cost.grid_samples = grid_samples as f64;
        cost.check()?;
        // A quarter of the brush reach: the query box then holds about
        // twice the vertices within reach instead of about three times.
        let cell =
            0.25 * (extent.size * self.settings.brush_scale + self.settings.influence) / scale;
        let sculptor = Sculptor::new(target.surface.clone(), cell);
        let mut cost = estimate_on(&sculptor, &self.settings, extent, scale, &paths)?;
        cost.grid_samples = grid_samples as f64;
        cost.check()?;
        Ok(Prepared {
            sculptor,
            cost,
            scale,
            poses,
            mirrored,
        })
    }
}

/// A stroke checked and ready to run ([`SculptStroke::apply_to`]).
struct Prepared {
    sculptor: Sculptor,
    cost: StrokeCost,
    scale: f64,
    poses: Vec<(BrushPose, f64)>,
    mirrored: Option<Vec<(BrushPose, f64)>>,
}
