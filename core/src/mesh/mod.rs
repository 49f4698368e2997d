//! Triangle meshes: the flat buffer every border uses, validation of the
//! closed 2-manifold invariants (with an exact self-intersection search and
//! checks at the precision a file stores), booleans (the printable union),
//! and STL / 3MF (millimetres) and OBJ / PLY (metres) files.

mod boolean;
mod error;
mod format;
mod obj;
mod ply;
mod precision;
mod selfx;
mod stl;
#[cfg(test)]
pub(crate) mod test_meshes;
mod threemf;
mod tri_meet;
mod trimesh;
mod union_tree;
pub(crate) mod validate;

pub use boolean::{
    difference, manifold_accepts, snap, union, union_snapped, union_snapped_with, BooleanCancel,
    BooleanError, UnionOperand,
};
pub use error::MeshIoError;
pub use format::{FileUnit, MeshFormat, PartNames, MESH_EXTENSIONS};
pub use obj::{read_obj, write_obj};
pub use ply::{read_ply, write_ply};
pub use precision::{at_precision, at_precision_in, Precision};
pub(crate) use selfx::triangles_cross;
pub use selfx::{self_intersections, SelfIntersections, MAX_EXACT_COORDINATE};
pub use stl::{read_stl, write_stl};
pub use threemf::{read_3mf, write_3mf};
pub use trimesh::{f64_le_bytes, u32_le_bytes, TriMesh};
pub use union_tree::{
    disjoint_groups, singletons, union_split, union_tree_nodes, unite_tree, UnionTree,
};
pub use validate::{
    problem_triangles, validate, ValidationReport, ValidationSettings, LISTED_PAIRS,
};
