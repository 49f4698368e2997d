//! Document objects: what each kind stores, and its evaluated mesh.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::math::Transform;
use crate::mesh::TriMesh;
use crate::solid::{tessellate, SolidShape};

use super::OpError;

/// An object of the document: its parameters and its evaluated mesh.
#[derive(Clone, Debug)]
pub struct Object {
    /// What the object is, with every parameter.
    pub kind: ObjectKind,
    /// The object's mesh in model space, evaluated when the object changed.
    /// Triangles carry the object's id as their source.
    pub mesh: Arc<TriMesh>,
}

/// The kinds of object a document can hold.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ObjectKind {
    /// A parametric solid (box, sphere, ...).
    Solid(Solid),
    /// An assembly of generalized cylinders; evaluates to the manifold
    /// union of its parts.
    GcAssembly(crate::gc::GcAssembly),
    /// A surface sculpted with warp brushes.
    SculptMesh(crate::sculpt::SculptMesh),
    /// A scene SDF built from placed library components (paper 2).
    SdfVolume(crate::sdf::SdfVolume),
    /// A styled curve network with its patches.
    CurveNetwork(crate::styling::CurveNetwork),
}

impl ObjectKind {
    /// The kind's name, as errors and reports say it.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Solid(_) => "solid",
            Self::GcAssembly(_) => "gc_assembly",
            Self::SculptMesh(_) => "sculpt_mesh",
            Self::SdfVolume(_) => "sdf_volume",
            Self::CurveNetwork(_) => "curve_network",
        }
    }

    /// Evaluates the object's mesh in model space.
    pub fn evaluate(&self) -> Result<TriMesh, OpError> {
        match self {
            Self::Solid(s) => s.evaluate(),
            // A part that cannot be meshed is a GC error, whichever path
            // found it; only union failures are assembly errors.
            Self::GcAssembly(a) => crate::assembly::union_mesh(a).map_err(|e| match e {
                crate::assembly::AssemblyError::Gc(g) => OpError::Gc(g),
                other => OpError::Assembly(other),
            }),
            Self::SculptMesh(s) => s.evaluate(),
            Self::SdfVolume(v) => Ok(v.evaluate()?),
            Self::CurveNetwork(n) => Ok(n.mesh()),
        }
    }
}

/// A parametric solid placed by a transform.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Solid {
    /// The shape and its sizes.
    pub shape: SolidShape,
    /// Segments around each circle.
    pub segments: u32,
    /// Placement in model space.
    pub transform: Transform,
}

impl Solid {
    /// Meshes the shape and places it.
    pub fn evaluate(&self) -> Result<TriMesh, OpError> {
        let affine = self.transform.to_affine()?;
        let mut mesh = tessellate(&self.shape, self.segments)?;
        mesh.transform(&affine);
        Ok(mesh)
    }
}
