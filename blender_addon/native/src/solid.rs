//! The parametric solids' kinds, for the add-on's menus. Their sizes
//! become shapes in the core's forms (`build_form`, through
//! `SolidShape::from_sizes`), so a host never spells out which size is a
//! radius and which a height.

use pyo3::prelude::*;
use shapewright::solid::SOLID_KINDS;

/// The solid kinds, in the order hosts list them.
#[pyfunction]
pub(crate) fn solid_kinds() -> Vec<&'static str> {
    SOLID_KINDS.to_vec()
}
