//! Document objects: what each kind stores, its name, its placement, and
//! its evaluated mesh.
//!
//! **Placement.** Every object can be moved, rotated and scaled by the
//! document ops (`set_transform`, `transform_by`). Kinds that carry their
//! own transform (solids, sculpts: their ops and tools already map world
//! input through it) are placed by that transform. The other kinds (GC
//! assemblies, SDF volumes, curve networks) keep their geometry in their own
//! frame and get an object-level [`Object::placement`] applied to their
//! mesh: moving a fused SDF result or a styled network never re-samples or
//! re-fits it. Edit ops on those kinds take positions in the object's own
//! frame (tools map world input through [`Object::placement`]).

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::math::Transform;
use crate::mesh::TriMesh;
use crate::solid::{tessellate, SolidShape};

use super::OpError;

/// An object of the document: its parameters, name, placement and
/// evaluated mesh.
#[derive(Clone, Debug)]
pub struct Object {
    /// What the object is, with every parameter.
    pub kind: ObjectKind,
    /// The user's name for it (`""`: unnamed; hosts then show the kind
    /// and id).
    pub name: String,
    /// The object-level placement of kinds without their own transform
    /// (identity for solids and sculpts, which place themselves; see the
    /// module doc).
    pub placement: Transform,
    /// The kind's mesh in its own frame (before [`Self::placement`]),
    /// evaluated when the kind changed. The same `Arc` as [`Self::mesh`]
    /// when the placement is the identity.
    pub local_mesh: Arc<TriMesh>,
    /// The object's mesh in model space, placed. Triangles carry the
    /// object's id as their source.
    pub mesh: Arc<TriMesh>,
    /// What evaluating the kind keeps for the next evaluation (a GC
    /// assembly's part meshes and partial unions, see
    /// [`crate::assembly::UnionCache`]); shared by every version of the
    /// object (its edits, the log's checkpoints, undo and redo). Not
    /// content: never saved or hashed, and the mesh is the same bits with
    /// or without it.
    pub cache: crate::assembly::UnionCache,
}

impl Object {
    /// Where the object is: its own transform for solids and sculpts, else
    /// its object-level placement.
    pub fn transform(&self) -> Transform {
        self.kind.own_transform().unwrap_or(self.placement)
    }
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
            Self::Solid(_) => Solid::NAME,
            Self::GcAssembly(_) => crate::gc::GcAssembly::NAME,
            Self::SculptMesh(_) => crate::sculpt::SculptMesh::NAME,
            Self::SdfVolume(_) => crate::sdf::SdfVolume::NAME,
            Self::CurveNetwork(_) => crate::styling::CurveNetwork::NAME,
        }
    }

    /// Evaluates the object's mesh in model space (before any object-level
    /// placement).
    pub fn evaluate(&self) -> Result<TriMesh, OpError> {
        self.evaluate_cached(&Default::default())
    }

    /// [`Self::evaluate`], reusing and filling `cache` (the same bits).
    pub fn evaluate_cached(&self, cache: &crate::assembly::UnionCache) -> Result<TriMesh, OpError> {
        match self {
            Self::Solid(s) => s.evaluate(),
            // A part that cannot be meshed is a GC error, whichever path
            // found it; only union failures are assembly errors.
            Self::GcAssembly(a) => {
                crate::assembly::union_mesh_cached(a, cache).map_err(|e| match e {
                    crate::assembly::AssemblyError::Gc(g) => OpError::Gc(g),
                    other => OpError::Assembly(other),
                })
            }
            Self::SculptMesh(s) => Ok(s.evaluate()?),
            Self::SdfVolume(v) => Ok(v.evaluate()?),
            Self::CurveNetwork(n) => Ok(n.mesh()),
        }
    }

    /// The kind's own placement, for kinds that carry one.
    pub fn own_transform(&self) -> Option<Transform> {
        match self {
            Self::Solid(s) => Some(s.transform),
            Self::SculptMesh(s) => Some(s.transform),
            _ => None,
        }
    }

    /// Sets the kind's own placement; `false` (and nothing changed) for
    /// kinds placed by the object.
    pub fn set_own_transform(&mut self, t: Transform) -> Result<bool, OpError> {
        match self {
            Self::Solid(s) => s.transform = t,
            Self::SculptMesh(s) => {
                crate::sculpt::model_scale(&t)?;
                s.transform = t;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// A Rust type that is one of the [`ObjectKind`]s: the one typed accessor
/// behind every "object of kind K, or a typed error" lookup
/// ([`super::Document::get_as`]).
pub trait KindOf: Clone + Sized {
    /// The kind's name (`"gc_assembly"`, ...), as [`ObjectKind::name`] says it.
    const NAME: &'static str;
    /// `kind` as this type, if it is one.
    fn of(kind: &ObjectKind) -> Option<&Self>;
    /// Wraps the value as an [`ObjectKind`].
    fn into_kind(self) -> ObjectKind;
}

macro_rules! kind_of {
    ($ty:ty, $variant:ident, $name:literal) => {
        impl KindOf for $ty {
            const NAME: &'static str = $name;
            fn of(kind: &ObjectKind) -> Option<&Self> {
                match kind {
                    ObjectKind::$variant(x) => Some(x),
                    _ => None,
                }
            }
            fn into_kind(self) -> ObjectKind {
                ObjectKind::$variant(self)
            }
        }
    };
}

kind_of!(Solid, Solid, "solid");
kind_of!(crate::gc::GcAssembly, GcAssembly, "gc_assembly");
kind_of!(crate::sculpt::SculptMesh, SculptMesh, "sculpt_mesh");
kind_of!(crate::sdf::SdfVolume, SdfVolume, "sdf_volume");
kind_of!(crate::styling::CurveNetwork, CurveNetwork, "curve_network");

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
