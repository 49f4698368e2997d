//! Mesh file formats by name, so every host picks readers and writers the
//! same way, and the length unit each one's numbers are in.
//!
//! The core models in metres; a file's unit is a writer's matter, converted
//! once when writing and once when reading (ARCHITECTURE "Units at the
//! borders"). The choice per format, and who assumes what:
//! - **STL: millimetres.** STL has no unit field; every slicer (PrusaSlicer,
//!   Cura, Bambu Studio, OrcaSlicer, Simplify3D) reads its numbers as
//!   millimetres, and STL is the format people print. (Blender's STL
//!   importer reads metres at scale 1: import ours with scale 0.001.)
//! - **3MF: millimetres, stated** (`unit="millimeter"` on the model): the
//!   format current slicers prefer. Readers honour every unit the 3MF core
//!   spec names (micron to metre, inch, foot).
//! - **OBJ and PLY: metres**, the core's own unit, stated in a header
//!   comment (`# units: metres`, `comment units: metres`). Both formats are
//!   unitless; they are interchange formats for modelling tools, which take
//!   one unit as one metre (Blender's OBJ and PLY importers at scale 1,
//!   MeshLab, Open3D, trimesh), while slicers read them as millimetres
//!   (PrusaSlicer's GUI then offers to scale a model that small up by
//!   1000). For printing, write STL or 3MF.
//!
//! Readers read the same units back (`info` shows a file at the size it
//! prints), so a file written and read again is the same model in metres.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use super::{
    read_3mf, read_obj, read_ply, read_stl, write_3mf, write_obj, write_ply, write_stl,
    MeshIoError, TriMesh,
};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Binary STL in millimetres (ASCII STL is read too).
    Stl,
    /// 3MF (3D Manufacturing Format) in millimetres: one object per
    /// connected piece, named after the document's objects.
    ThreeMf,
    /// Wavefront OBJ in metres.
    Obj,
    /// Binary little-endian PLY in metres (ascii and big-endian PLY are
    /// read too).
    Ply,
}

/// The length unit a file's numbers are in.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum FileUnit {
    /// Metres: the core's unit (file value = model value).
    #[default]
    Metre,
    /// Millimetres: file value = model value x 1000.
    Millimetre,
}

impl FileUnit {
    /// File units per metre (1 or 1000).
    pub fn per_metre(self) -> f64 {
        match self {
            Self::Metre => 1.0,
            Self::Millimetre => 1000.0,
        }
    }

    /// The unit's symbol (`m`, `mm`).
    pub fn symbol(self) -> &'static str {
        match self {
            Self::Metre => "m",
            Self::Millimetre => "mm",
        }
    }
}

/// The names of the objects whose triangles a mesh holds (by source id),
/// for formats that name their parts (3MF). An id without a name is named
/// `object ID`.
pub type PartNames = BTreeMap<u32, String>;

/// Every extension the mesh writers take, as messages list them.
pub const MESH_EXTENSIONS: &str = ".stl, .3mf, .obj or .ply";

impl MeshFormat {
    /// The format named by a path's extension (case-insensitive), if any.
    pub fn from_path(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "stl" => Some(Self::Stl),
            "3mf" => Some(Self::ThreeMf),
            "obj" => Some(Self::Obj),
            "ply" => Some(Self::Ply),
            _ => None,
        }
    }

    /// The length unit of the numbers this format's writer writes (and its
    /// reader assumes where the file does not say).
    pub fn unit(self) -> FileUnit {
        match self {
            Self::Stl | Self::ThreeMf => FileUnit::Millimetre,
            Self::Obj | Self::Ply => FileUnit::Metre,
        }
    }

    /// The format's usual name (`STL`, `3MF`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Self::Stl => "STL",
            Self::ThreeMf => "3MF",
            Self::Obj => "OBJ",
            Self::Ply => "PLY",
        }
    }

    /// Writes `mesh` (model units: metres) in this format, in its unit.
    /// 3MF objects are named `object ID`; use [`Self::write_named`] to give
    /// them the document's names.
    pub fn write(self, mesh: &TriMesh, w: &mut impl Write) -> std::io::Result<()> {
        self.write_named(mesh, &PartNames::new(), w)
    }

    /// Writes `mesh` in this format, naming its parts (3MF) by the objects
    /// their triangles come from. OBJ and PLY carry vertex normals: the
    /// mesh's own, or computed when it has none ([`TriMesh::with_normals`]:
    /// a boolean's result, a moved mesh).
    pub fn write_named(
        self,
        mesh: &TriMesh,
        names: &PartNames,
        w: &mut impl Write,
    ) -> std::io::Result<()> {
        match self {
            Self::Stl => write_stl(mesh, w),
            Self::ThreeMf => write_3mf(mesh, names, w),
            Self::Obj => write_obj(&mesh.with_normals(), w),
            Self::Ply => write_ply(&mesh.with_normals(), w),
        }
    }

    /// Reads a mesh in this format, in model units (metres).
    pub fn read(self, bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
        match self {
            Self::Stl => read_stl(bytes),
            Self::ThreeMf => read_3mf(bytes),
            Self::Obj => read_obj(bytes),
            Self::Ply => read_ply(bytes),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solid::{tessellate, SolidShape};

    /// A union's result has no vertex normals; its OBJ and PLY files still
    /// carry one per vertex, the angle-weighted ones, while STL (facet
    /// normals from the corners) is unchanged.
    #[test]
    fn obj_and_ply_of_a_union_carry_its_vertex_normals() {
        let ball = |x: f64, id: u32| {
            let mut m = tessellate(&SolidShape::Sphere { radius: 0.02 }, 24).expect("sphere");
            m.transform(&glam::DAffine3::from_translation(glam::DVec3::new(
                x, 0.0, 0.0,
            )));
            m.set_source(id);
            m
        };
        let (a, b) = (ball(0.0, 1), ball(0.025, 2));
        let u = crate::mesh::union(&[&a, &b]).expect("union");
        assert!(u.normals.is_empty(), "the union computes no normals");
        let mut want = u.clone();
        want.compute_normals();

        let mut obj = Vec::new();
        MeshFormat::Obj.write(&u, &mut obj).unwrap();
        let obj = String::from_utf8(obj).unwrap();
        let vn: Vec<[f64; 3]> = obj
            .lines()
            .filter_map(|l| l.strip_prefix("vn "))
            .map(|l| {
                let x: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                [x[0], x[1], x[2]]
            })
            .collect();
        assert_eq!(vn, want.normals, "OBJ: one exact vn per vertex");
        assert!(obj.lines().any(|l| l.starts_with("f ") && l.contains("//")));

        let mut ply = Vec::new();
        MeshFormat::Ply.write(&u, &mut ply).unwrap();
        let head = String::from_utf8_lossy(&ply[..ply.len().min(400)]).into_owned();
        assert!(
            head.contains("property float nx"),
            "PLY has normals: {head}"
        );

        let (mut stl_u, mut stl_w) = (Vec::new(), Vec::new());
        MeshFormat::Stl.write(&u, &mut stl_u).unwrap();
        MeshFormat::Stl.write(&want, &mut stl_w).unwrap();
        assert_eq!(stl_u, stl_w);
    }
}
