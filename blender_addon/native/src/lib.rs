//! Python bindings of the Shapewright core (`shapewright._native`), used by
//! the Blender add-on. Thin by design (tokenizers' bindings are the
//! model): each file mirrors one core module or one idea of the border,
//! core types cross as `#[pyclass]` newtypes (`Placement`, `Pose`,
//! `InputFrame`, `Presence`, `PaletteView`) or as Python dicts and lists
//! depythonized in Rust (`convert.rs`: ops, form values, trace lines; numbers
//! checked on the way in), never as JSON text; errors convert in
//! `error.rs`; heavy work runs with the GIL released, long work on
//! threads of its own (`jobs.rs`, `autosave.rs`); no geometry is computed
//! here. `python/shapewright/_native.pyi` states the whole surface (a
//! test keeps it true).

mod adopt;
mod autosave;
mod convert;
mod doc;
mod error;
mod forms;
mod input;
mod interact;
mod jobs;
mod lines;
mod mesh;
mod objects;
mod parametric;
mod placement;
mod sdf;
mod shared;
mod solid;
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
    m.add_class::<placement::Placement>()?;
    m.add_class::<placement::Pose>()?;
    m.add_class::<input::Controller>()?;
    m.add_class::<input::InputFrame>()?;
    m.add_class::<interact::InputSession>()?;
    m.add_class::<interact::PaletteView>()?;
    m.add_class::<interact::PaletteDraw>()?;
    m.add_class::<interact::PaletteLabel>()?;
    m.add_class::<shared::Presence>()?;
    m.add_class::<jobs::ExportJob>()?;
    m.add_class::<autosave::Autosaver>()?;
    m.add_class::<forms::Built>()?;
    m.add_function(wrap_pyfunction!(interact::action_map, m)?)?;
    m.add_function(wrap_pyfunction!(interact::trace_format, m)?)?;
    m.add_function(wrap_pyfunction!(interact::tool_names, m)?)?;
    m.add_function(wrap_pyfunction!(usd::save_usd, m)?)?;
    m.add_function(wrap_pyfunction!(usd::load_usd, m)?)?;
    m.add_function(wrap_pyfunction!(usd::import_usd, m)?)?;
    m.add_function(wrap_pyfunction!(usd::import_usd_text, m)?)?;
    m.add_function(wrap_pyfunction!(usd::usd_text, m)?)?;
    m.add_function(wrap_pyfunction!(sdf::library_names, m)?)?;
    m.add_function(wrap_pyfunction!(solid::solid_kinds, m)?)?;
    m.add_function(wrap_pyfunction!(parametric::parametric_parts, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::validate_buffers, m)?)?;
    m.add_function(wrap_pyfunction!(doc::op_names, m)?)?;
    m.add_function(wrap_pyfunction!(doc::op_schema, m)?)?;
    m.add_function(wrap_pyfunction!(forms::op_forms, m)?)?;
    m.add_function(wrap_pyfunction!(forms::build_form, m)?)?;
    m.add("OP_FORMAT_VERSION", shapewright::doc::OP_FORMAT_VERSION)?;
    // How often a host sends its presence: the core's rate, one number for
    // both hosts (issue 36).
    m.add("PRESENCE_HZ", shapewright::doc::shared::PRESENCE_HZ)?;
    error::register(m)?;
    Ok(())
}
