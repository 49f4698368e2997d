//! Mesh file formats by name, so every host picks readers and writers the
//! same way.

use std::io::Write;
use std::path::Path;

use super::{read_obj, read_ply, read_stl, write_obj, write_ply, write_stl, MeshIoError, TriMesh};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Binary STL (ASCII STL is read too).
    Stl,
    /// Wavefront OBJ.
    Obj,
    /// Binary little-endian PLY (ascii and big-endian PLY are read too).
    Ply,
}

impl MeshFormat {
    /// The format named by a path's extension (case-insensitive), if any.
    pub fn from_path(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "stl" => Some(Self::Stl),
            "obj" => Some(Self::Obj),
            "ply" => Some(Self::Ply),
            _ => None,
        }
    }

    /// Writes `mesh` in this format.
    pub fn write(self, mesh: &TriMesh, w: &mut impl Write) -> std::io::Result<()> {
        match self {
            Self::Stl => write_stl(mesh, w),
            Self::Obj => write_obj(mesh, w),
            Self::Ply => write_ply(mesh, w),
        }
    }

    /// Reads a mesh in this format.
    pub fn read(self, bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
        match self {
            Self::Stl => read_stl(bytes),
            Self::Obj => read_obj(bytes),
            Self::Ply => read_ply(bytes),
        }
    }
}
