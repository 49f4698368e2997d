//! Meshes across the border: flat little-endian buffers that numpy views
//! without copying (`np.frombuffer`), and validation.

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use shapewright::mesh::{f64_le_bytes, u32_le_bytes, validate, TriMesh, ValidationReport};

/// A mesh as `(positions: f64 x 3n, triangles: u32 x 3m, sources: u32 x m)`
/// byte buffers, positions multiplied by `units_per_metre` (a host's
/// scene units; 1 keeps metres) in the same pass.
pub(crate) fn buffers<'py>(
    py: Python<'py>,
    m: &TriMesh,
    units_per_metre: f64,
) -> (
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
) {
    (
        PyBytes::new(
            py,
            &f64_le_bytes(m.positions.iter().flatten(), units_per_metre),
        ),
        PyBytes::new(py, &u32_le_bytes(m.triangles.iter().flatten())),
        PyBytes::new(py, &u32_le_bytes(&m.tri_source)),
    )
}

/// A validation report as a dict.
pub(crate) fn report_dict<'py>(
    py: Python<'py>,
    r: &ValidationReport,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("closed_manifold", r.is_closed_manifold())?;
    d.set_item("problems", r.problems())?;
    d.set_item("vertices", r.vertex_count)?;
    d.set_item("triangles", r.triangle_count)?;
    d.set_item("components", r.components)?;
    d.set_item("euler_characteristic", r.euler_characteristic)?;
    d.set_item("genus", r.genus)?;
    d.set_item("volume", r.signed_volume)?;
    d.set_item("area", r.area)?;
    d.set_item("bbox", r.bbox)?;
    Ok(d)
}

/// Validates a mesh given as flat buffers (positions f64 x 3n, triangles
/// u32 x 3m), e.g. a Blender mesh read with `foreach_get`.
#[pyfunction]
pub(crate) fn validate_buffers<'py>(
    py: Python<'py>,
    positions: &[u8],
    triangles: &[u8],
) -> PyResult<Bound<'py, PyDict>> {
    if !positions.len().is_multiple_of(24) || !triangles.len().is_multiple_of(12) {
        return Err(crate::error::ParseError::new_err(format!(
            "positions must be 3 x f64 per vertex ({} bytes given) and triangles 3 x u32 per triangle ({} bytes given)",
            positions.len(),
            triangles.len()
        )));
    }
    let f = |c: &[u8]| f64::from_le_bytes(c.try_into().unwrap_or([0; 8]));
    let u = |c: &[u8]| u32::from_le_bytes(c.try_into().unwrap_or([0; 4]));
    let mesh = TriMesh::new(
        positions
            .chunks_exact(24)
            .map(|p| [f(&p[0..8]), f(&p[8..16]), f(&p[16..24])])
            .collect(),
        triangles
            .chunks_exact(12)
            .map(|t| [u(&t[0..4]), u(&t[4..8]), u(&t[8..12])])
            .collect(),
    );
    let report = py.detach(|| validate(&mesh, &Default::default()));
    report_dict(py, &report)
}
