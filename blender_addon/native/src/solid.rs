//! Parametric solids from the sizes a person types (`SolidShape::from_sizes`):
//! the one mapping from a kind and its dimensions to a shape, so a host
//! never spells out which size is a radius and which a height.

use pyo3::prelude::*;
use shapewright::solid::{SolidShape, SOLID_KINDS};

use crate::convert::{from_py, into_py};
use crate::error::OpRejected;

/// The solid kinds, in the order hosts list them.
#[pyfunction]
pub(crate) fn solid_kinds() -> Vec<&'static str> {
    SOLID_KINDS.to_vec()
}

/// The shape (as an op holds it, a dict) of kind `kind` whose bounding box
/// has the edge lengths `dimensions` (metres; round shapes take their
/// diameter from x); refuses sizes that make no such solid, saying which.
#[pyfunction]
pub(crate) fn solid_shape<'py>(
    py: Python<'py>,
    kind: &str,
    dimensions: [f64; 3],
) -> PyResult<Bound<'py, PyAny>> {
    crate::convert::check_finite("dimensions", &dimensions)?;
    let shape =
        SolidShape::from_sizes(kind, dimensions).map_err(|e| OpRejected::new_err(e.to_string()))?;
    into_py(py, &shape)
}

/// The dimensions of a shape dict (the inverse of `solid_shape`).
#[pyfunction]
pub(crate) fn solid_dimensions(shape: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    let shape: SolidShape = from_py(shape, "shape")?;
    Ok(shape.dimensions())
}
