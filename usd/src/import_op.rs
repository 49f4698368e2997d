//! Geometry authored elsewhere brought into a document (issue 7, Build 3):
//! as an SDF library component, a sculpt base mesh, or a grid brush.
//!
//! The meshes of the file ([`crate::import_file`]: triangulated, xformOps
//! applied, converted to Z-up meters) are combined into one mesh, which
//! then becomes:
//! - a component: the op `sdf_import_component` (paper 2 §3), which checks
//!   that the mesh is a closed 2-manifold and stores it in the volume;
//! - a sculpt base: the op `sculpt_create` with `base = mesh` (paper 4);
//! - a brush: a [`BrushShape::Grid`] sampled from the mesh's signed
//!   distance (`core::sdf::mesh_to_sdf`). A brush is a parameter of the
//!   `sculpt_stroke` op, not a document object, so this returns the shape
//!   for the caller to use in its strokes.
//!
//! The ops carry the mesh itself (every parameter explicit), so a document
//! that imported a file replays without the file.

use std::path::Path;

use shapewright::doc::{Create, Edit, ObjectId, ObjectKind, Op, OpLog, OpOutcome};
use shapewright::math::Transform;
use shapewright::mesh::TriMesh;
use shapewright::sculpt::{BrushShape, DistanceGrid, SculptBase, SculptCreate};
use shapewright::sdf::{SdfCreate, SdfImportComponent};

use crate::import::combined;
use crate::{import_file, ImportError, ImportOptions};

/// What imported geometry becomes.
#[derive(Clone, Debug, PartialEq)]
pub enum ImportTarget {
    /// A library component named `name` of the SDF volume `volume`; without
    /// a volume, the document's only SDF volume, or a new one
    /// (`sdf_create` at the default step) when it has none.
    Component {
        /// The volume, if chosen.
        volume: Option<ObjectId>,
        /// The component's name (unique in the volume).
        name: String,
    },
    /// A new sculpt object with the mesh as its base, placed by `transform`.
    SculptBase {
        /// Placement (uniform positive scale).
        transform: Transform,
    },
}

/// The meshes of `path` (filtered by `options.prefix`) as one mesh.
pub fn import_combined(path: &Path, options: &ImportOptions) -> Result<TriMesh, ImportError> {
    Ok(combined(&import_file(path, options)?))
}

fn apply(log: &mut OpLog, op: Op) -> Result<OpOutcome, ImportError> {
    let name = op.name();
    log.apply(op).map_err(|e| ImportError::Apply {
        op: name,
        message: e.to_string(),
    })
}

/// The volume a component without one goes into (see [`ImportTarget`]).
fn volume_for(log: &mut OpLog) -> Result<ObjectId, ImportError> {
    let volumes: Vec<ObjectId> = log
        .document()
        .objects()
        .filter(|(_, o)| matches!(o.kind, ObjectKind::SdfVolume(_)))
        .map(|(id, _)| id)
        .collect();
    match volumes.as_slice() {
        [only] => Ok(*only),
        [] => {
            let step = shapewright::sdf::volume::DEFAULT_STEP;
            apply(log, Op::SdfCreate(Create(SdfCreate { step })))?
                .created
                .ok_or_else(|| ImportError::Apply {
                    op: "sdf_create",
                    message: "created no object".to_owned(),
                })
        }
        _ => Err(ImportError::Apply {
            op: "sdf_import_component",
            message: format!("the document has {} SDF volumes; name one", volumes.len()),
        }),
    }
}

/// Imports the meshes of `path` into `log` as `target`: applies the op
/// (and an `sdf_create` first when a component needs a new volume) and
/// returns the import op's outcome.
pub fn import_into(
    log: &mut OpLog,
    path: &Path,
    options: &ImportOptions,
    target: ImportTarget,
) -> Result<OpOutcome, ImportError> {
    let mesh = import_combined(path, options)?;
    let positions = mesh.positions;
    let triangles = mesh.triangles;
    let op = match target {
        ImportTarget::Component { volume, name } => {
            let volume = match volume {
                Some(v) => v,
                None => volume_for(log)?,
            };
            Op::SdfImportComponent(Edit::new(
                volume,
                SdfImportComponent {
                    name,
                    positions,
                    triangles,
                },
            ))
        }
        ImportTarget::SculptBase { transform } => Op::SculptCreate(Create(SculptCreate {
            base: SculptBase::Mesh {
                positions,
                triangles,
            },
            transform,
        })),
    };
    apply(log, op)
}

/// A grid brush from the meshes of `path`: their signed distance sampled
/// every `step` over their box grown by `padding`, in the file's (Z-up,
/// converted) frame. The mesh must be closed and oriented.
pub fn import_brush(
    path: &Path,
    options: &ImportOptions,
    step: f64,
    padding: f64,
) -> Result<BrushShape, ImportError> {
    let mesh = import_combined(path, options)?;
    let bad = |message: String| ImportError::BadMesh {
        path: path.display().to_string(),
        message,
    };
    let sdf = shapewright::sdf::mesh_to_sdf(&mesh, step, padding)
        .map_err(|e| bad(format!("as a brush: {e}")))?;
    let dim = |n: usize| u32::try_from(n).map_err(|_| bad(format!("{n} grid samples")));
    let shape = BrushShape::Grid(DistanceGrid {
        origin: sdf.origin,
        step: sdf.step,
        dims: [dim(sdf.dims[0])?, dim(sdf.dims[1])?, dim(sdf.dims[2])?],
        values: sdf.values.iter().map(|&v| f64::from(v)).collect(),
    });
    shape
        .validate()
        .map_err(|e| bad(format!("as a brush: {e}")))?;
    Ok(shape)
}
