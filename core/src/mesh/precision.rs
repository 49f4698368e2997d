//! The precision a mesh file stores, and the mesh a reader of that file
//! sees.
//!
//! A union that is valid in f64 can collapse triangles or pinch edges once
//! its coordinates are rounded to f32 for STL, and the STL reader then
//! welds bit-identical corners into one vertex, which can join vertices the
//! f64 mesh kept apart. [`at_precision`] does exactly what writing and
//! reading back does (round each coordinate to nearest, then weld
//! bit-identical positions), so validating its result validates the file.
//! Negative zero is written as positive zero, so that readers welding by
//! bits and readers welding by value see the same vertices.

use super::{MeshFormat, TriMesh};

/// How a file stores coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// IEEE single precision (binary STL, PLY, USD `point3f[]`).
    F32,
    /// IEEE double precision, or text that round-trips it exactly (our OBJ
    /// writer prints the shortest round-trip form of every f64).
    F64,
}

impl Precision {
    /// The precision our writer uses for `format`.
    pub fn of_format(format: MeshFormat) -> Self {
        match format {
            MeshFormat::Stl | MeshFormat::Ply => Self::F32,
            MeshFormat::Obj => Self::F64,
        }
    }

    /// `x` as the file stores it (f32: rounded to nearest, overflow to
    /// infinity), with negative zero made positive.
    pub fn round(self, x: f64) -> f64 {
        match self {
            Self::F32 => (x as f32) as f64 + 0.0,
            Self::F64 => x + 0.0,
        }
    }

    /// Largest finite magnitude the precision can hold.
    pub fn max_finite(self) -> f64 {
        match self {
            Self::F32 => f32::MAX as f64,
            Self::F64 => f64::MAX,
        }
    }

    /// The name a report prints.
    pub fn name(self) -> &'static str {
        match self {
            Self::F32 => "float32",
            Self::F64 => "float64",
        }
    }
}

/// `mesh` as a reader of a file written at `precision` sees it: every
/// coordinate rounded, then vertices with bit-identical positions welded
/// (the first kept). Triangles, their order and their sources are kept,
/// so a triangle that collapsed shows up as a repeated index; normals are
/// recomputed.
pub fn at_precision(mesh: &TriMesh, precision: Precision) -> TriMesh {
    let mut out = TriMesh {
        positions: mesh
            .positions
            .iter()
            .map(|p| p.map(|x| precision.round(x)))
            .collect(),
        normals: Vec::new(),
        triangles: mesh.triangles.clone(),
        tri_source: mesh.tri_source.clone(),
    };
    out.weld_exact();
    out.compute_normals();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::test_meshes::tetra;
    use crate::mesh::{read_stl, validate, write_stl};

    #[test]
    fn matches_writing_and_reading_an_stl() {
        let mut m = tetra();
        // Two corners 1e-12 apart in f64 become one in f32.
        m.positions.push([1.0 + 1e-12, 0.0, 0.0]);
        m.triangles[2] = [4, 2, 3];
        let mut bytes = Vec::new();
        write_stl(&m, &mut bytes).unwrap();
        let back = read_stl(&bytes).unwrap();
        let ours = at_precision(&m, Precision::F32);
        let used = |t: &TriMesh| {
            let mut v: Vec<[u64; 3]> = t
                .triangles
                .iter()
                .flat_map(|tri| tri.map(|i| t.positions[i as usize]))
                .map(|p| p.map(f64::to_bits))
                .collect();
            v.sort();
            v.dedup();
            v
        };
        assert_eq!(used(&ours), used(&back));
        // The f64 mesh has a crack (two corners apart); the file does not.
        assert!(!validate(&m, &Default::default()).is_closed());
        assert!(validate(&ours, &Default::default()).is_closed());
    }

    #[test]
    fn rounding_names_its_limits() {
        assert_eq!(Precision::F32.round(1e39), f64::INFINITY);
        assert_eq!(Precision::F32.round(-0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(Precision::F64.round(0.1), 0.1);
        assert_eq!(Precision::of_format(MeshFormat::Stl), Precision::F32);
        assert_eq!(Precision::of_format(MeshFormat::Obj), Precision::F64);
    }
}
