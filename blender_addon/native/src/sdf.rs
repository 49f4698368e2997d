//! The SDF component library's names (for the CSG panel's menu).

use pyo3::prelude::*;

/// Names of the starter component library, in the core's order.
#[pyfunction]
pub(crate) fn library_names() -> Vec<&'static str> {
    shapewright::sdf::library::STARTER_NAMES.to_vec()
}
