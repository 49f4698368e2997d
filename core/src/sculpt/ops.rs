//! The sculpt object kind and its ops: `sculpt_create` makes a
//! [`SculptMesh`] from a base shape or any closed mesh; `sculpt_stroke`
//! applies one whole stroke (its sampled path is stored in the op, so
//! undo, redo and replay reproduce it bit for bit).

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::base::{geodesic_sphere, grid_box, sphere_frequency};
use super::brush::{check_finite, positive, BrushPose, BrushShape};
use super::halfedge::HalfEdgeMesh;
use super::stroke::{run_stroke, Sculptor, StrokeSample, StrokeSettings};
use super::SculptError;
use crate::doc::{Document, ObjectId, ObjectKind, OpError, OpOutcome};
use crate::math::Transform;
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
    pub fn evaluate(&self) -> Result<TriMesh, OpError> {
        let affine = self.transform.to_affine()?;
        let mut m = self.surface.to_trimesh();
        m.transform(&affine);
        Ok(m)
    }
}

/// What to start sculpting from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum SculptBase {
    /// A geodesic sphere centred on the origin.
    Sphere {
        /// Radius.
        radius: f64,
        /// Target edge length.
        edge_length: f64,
    },
    /// A box centred on the origin.
    Box {
        /// Full sizes along x, y, z.
        size: [f64; 3],
        /// Target edge length.
        edge_length: f64,
    },
    /// A thin box in the xy plane.
    Slab {
        /// Full sizes along x and y.
        size: [f64; 2],
        /// Thickness along z.
        thickness: f64,
        /// Target edge length.
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
        positions: Vec<[f64; 3]>,
        /// Triangles, counter-clockwise from outside.
        triangles: Vec<[u32; 3]>,
    },
}

/// `sculpt_create`: a new sculpt object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SculptCreate {
    /// The base shape.
    pub base: SculptBase,
    /// Placement; its scale must be uniform and positive.
    #[serde(default)]
    pub transform: Transform,
}

/// `sculpt_stroke`: one stroke on a sculpt object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SculptStroke {
    /// The sculpt object.
    pub id: ObjectId,
    /// Brush, warp, weights and resolution settings.
    pub settings: StrokeSettings,
    /// The sampled path, in world space.
    pub samples: Vec<StrokeSample>,
}

fn model_scale(t: &Transform) -> Result<f64, SculptError> {
    let [a, b, c] = t.scale;
    if a != b || b != c || a.is_nan() || a <= 0.0 {
        return Err(SculptError::NonUniformScale(t.scale));
    }
    Ok(a)
}

/// Applies `sculpt_create`.
pub fn apply_create(doc: &mut Document, op: &SculptCreate) -> Result<OpOutcome, OpError> {
    op.transform.validate()?;
    model_scale(&op.transform)?;
    let mesh = match &op.base {
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
        SculptBase::Object { id } => (*doc.get(*id)?.mesh).clone(),
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
    let surface = HalfEdgeMesh::from_trimesh(&mesh, "base")?;
    let id = doc.insert(ObjectKind::SculptMesh(SculptMesh {
        surface,
        transform: op.transform,
    }))?;
    Ok(OpOutcome { created: Some(id) })
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

/// Applies `sculpt_stroke`.
pub fn apply_stroke(doc: &mut Document, op: &SculptStroke) -> Result<OpOutcome, OpError> {
    let obj = match &doc.get(op.id)?.kind {
        ObjectKind::SculptMesh(s) => s,
        #[allow(unreachable_patterns)]
        other => {
            return Err(OpError::WrongKind {
                id: op.id,
                op: "sculpt_stroke",
                expected: "sculpt_mesh",
                found: other.name(),
            })
        }
    };
    let (scale, poses) = stroke_poses(&obj.transform, &op.settings, &op.samples)?;
    // A mesh brush becomes a grid here, from the document as it is before
    // this stroke (so replay rebuilds the same brush).
    let resolved;
    let settings = match &op.settings.brush {
        BrushShape::Mesh(m) => {
            resolved = StrokeSettings {
                brush: BrushShape::Grid(m.to_grid(doc)?),
                ..op.settings.clone()
            };
            &resolved
        }
        _ => &op.settings,
    };
    // A quarter of the brush reach: the query box then holds about twice
    // the vertices within reach instead of about three times.
    let cell = 0.25 * (settings.brush_size() + settings.influence) / scale;
    let mut sculptor = Sculptor::new(obj.surface.clone(), cell);
    let transform = obj.transform;
    run_stroke(&mut sculptor, &settings.brush, settings, scale, &poses);
    let surface = sculptor.into_mesh();
    doc.replace(
        op.id,
        ObjectKind::SculptMesh(SculptMesh { surface, transform }),
    )?;
    Ok(OpOutcome::default())
}
