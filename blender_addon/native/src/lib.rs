//! Python bindings of the Shapewright core (`shapewright._native`), used by
//! the Blender add-on. Thin by design: each file mirrors one core module,
//! core types are wrapped in newtypes, errors convert
//! in `error.rs`, heavy work runs with the GIL released, and no geometry is
//! computed here.

mod doc;
mod error;
mod interact;
mod jobs;
mod mesh;
mod parametric;
mod sdf;
mod sketch;
mod usd;

use pyo3::prelude::*;

/// mimalloc for this library's own allocations (Blender's are untouched):
/// the system allocator returns and re-faults large blocks on every mesh
/// update (see the workspace manifest).
#[global_allocator]
static ALLOC: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The native module.
#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<doc::Session>()?;
    m.add_class::<interact::InputSession>()?;
    m.add_function(wrap_pyfunction!(interact::action_map_json, m)?)?;
    m.add_function(wrap_pyfunction!(interact::trace_format, m)?)?;
    m.add_function(wrap_pyfunction!(interact::tool_names, m)?)?;
    m.add_function(wrap_pyfunction!(usd::save_usd, m)?)?;
    m.add_function(wrap_pyfunction!(sdf::library_names, m)?)?;
    m.add_function(wrap_pyfunction!(usd::load_usd, m)?)?;
    m.add_function(wrap_pyfunction!(usd::import_usd, m)?)?;
    m.add_function(wrap_pyfunction!(usd::import_usd_text, m)?)?;
    m.add_function(wrap_pyfunction!(usd::usd_text, m)?)?;
    m.add_class::<jobs::ExportJob>()?;
    m.add_function(wrap_pyfunction!(parametric::parametric_parts, m)?)?;
    m.add_function(wrap_pyfunction!(sketch::sketch_spine, m)?)?;
    m.add_function(wrap_pyfunction!(sketch::child_from_stroke, m)?)?;
    m.add_function(wrap_pyfunction!(sketch::replace_spine_from_stroke, m)?)?;
    m.add_function(wrap_pyfunction!(sketch::match_section, m)?)?;
    m.add_function(wrap_pyfunction!(sketch::profile_radius, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::validate_buffers, m)?)?;
    m.add_function(wrap_pyfunction!(doc::op_names, m)?)?;
    m.add_function(wrap_pyfunction!(doc::op_schema_json, m)?)?;
    m.add("OP_FORMAT_VERSION", shapewright::doc::OP_FORMAT_VERSION)?;
    error::register(m)?;
    Ok(())
}
