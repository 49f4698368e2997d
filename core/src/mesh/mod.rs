//! Triangle meshes: the flat buffer every border uses, validation of the
//! closed 2-manifold invariants, booleans (the printable union), and
//! OBJ / STL / PLY files.

mod boolean;
mod error;
mod format;
mod obj;
mod ply;
mod stl;
#[cfg(test)]
mod test_meshes;
mod trimesh;
mod validate;

pub use boolean::{difference, union, BooleanError};
pub use error::MeshIoError;
pub use format::MeshFormat;
pub use obj::{read_obj, write_obj};
pub use ply::{read_ply, write_ply};
pub use stl::{read_stl, write_stl};
pub use trimesh::TriMesh;
pub use validate::{validate, ValidationReport, ValidationSettings};
