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
//!
//! A file in millimetres rounds the millimetre value, not the metre value
//! ([`at_precision_in`]): the model a reader sees is `f32(x * 1000) / 1000`
//! in metres, which the writer turns back into exactly the same `f32`
//! (the division's error is far below half a float32 step), so validating
//! it still validates the file, bit for bit.

use super::{FileUnit, MeshFormat, TriMesh};

/// How a file stores coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// IEEE single precision (binary STL, 3MF as we write it, PLY, USD
    /// `point3f[]`).
    F32,
    /// IEEE double precision, or text that round-trips it exactly (our OBJ
    /// writer prints the shortest round-trip form of every f64).
    F64,
}

impl Precision {
    /// The precision our writer uses for `format`.
    pub fn of_format(format: MeshFormat) -> Self {
        match format {
            MeshFormat::Stl | MeshFormat::ThreeMf | MeshFormat::Ply => Self::F32,
            MeshFormat::Obj => Self::F64,
        }
    }

    /// `x` as the file stores it (f32: rounded to nearest, overflow to
    /// infinity), with negative zero made positive.
    pub fn round(self, x: f64) -> f64 {
        self.round_in(x, FileUnit::Metre)
    }

    /// `x` (metres) as a file in `unit` stores it and a reader converts it
    /// back to metres: `x * per_metre` rounded to the precision, divided by
    /// `per_metre`, negative zero made positive. Metres: [`Self::round`].
    pub fn round_in(self, x: f64, unit: FileUnit) -> f64 {
        let s = unit.per_metre();
        if s == 1.0 {
            return match self {
                Self::F32 => (x as f32) as f64 + 0.0,
                Self::F64 => x + 0.0,
            };
        }
        match self {
            Self::F32 => ((x * s) as f32) as f64 / s + 0.0,
            Self::F64 => (x * s) / s + 0.0,
        }
    }

    /// Largest finite magnitude the precision can hold.
    pub fn max_finite(self) -> f64 {
        match self {
            Self::F32 => f32::MAX as f64,
            Self::F64 => f64::MAX,
        }
    }

    /// Largest finite magnitude in metres a file in `unit` can hold.
    pub fn max_finite_in(self, unit: FileUnit) -> f64 {
        self.max_finite() / unit.per_metre()
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
    at_precision_in(mesh, precision, FileUnit::Metre)
}

/// `mesh` as a reader of a file written at `precision` in `unit` sees it,
/// back in metres ([`Precision::round_in`], then welded as
/// [`at_precision`] does).
pub fn at_precision_in(mesh: &TriMesh, precision: Precision, unit: FileUnit) -> TriMesh {
    let mut out = TriMesh {
        positions: mesh
            .positions
            .iter()
            .map(|p| p.map(|x| precision.round_in(x, unit)))
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
        let ours = at_precision_in(&m, Precision::F32, FileUnit::Millimetre);
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
        assert_eq!(Precision::of_format(MeshFormat::ThreeMf), Precision::F32);
        assert_eq!(Precision::of_format(MeshFormat::Obj), Precision::F64);
        let mm = FileUnit::Millimetre;
        assert_eq!(Precision::F32.max_finite_in(mm), f32::MAX as f64 / 1000.0);
        assert_eq!(
            Precision::F32.round_in(-0.0, mm).to_bits(),
            0.0f64.to_bits()
        );
    }

    /// A file in millimetres stores `f32(x * 1000)`, not `f32(x) * 1000`:
    /// the mesh the print path validates must be the one the STL holds,
    /// bit for bit once read back, or the check is of another mesh.
    #[test]
    fn millimetre_rounding_is_what_the_stl_holds() {
        let mut m = tetra();
        for p in &mut m.positions {
            *p = p.map(|x| x * 0.123_456_789_123 + 0.071_234_567_891);
        }
        let mut bytes = Vec::new();
        write_stl(&m, &mut bytes).unwrap();
        let back = read_stl(&bytes).unwrap();
        let bits = |t: &TriMesh| {
            let mut v: Vec<[u64; 3]> = t.positions.iter().map(|p| p.map(f64::to_bits)).collect();
            v.sort();
            v
        };
        let mm = at_precision_in(&m, Precision::F32, FileUnit::Millimetre);
        assert_eq!(bits(&back), bits(&mm));
        // Rounding the metres instead gives other values: a different mesh.
        let metres = at_precision(&m, Precision::F32);
        assert_ne!(bits(&back), bits(&metres));
        // Writing the validated mesh again stores the same values.
        let mut again = Vec::new();
        write_stl(&mm, &mut again).unwrap();
        assert_eq!(bits(&read_stl(&again).unwrap()), bits(&mm));
    }
}
