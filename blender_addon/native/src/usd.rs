//! USD save and load of a document with its op log, through
//! `shapewright-usd` (usda with the ops, the cursor and a snapshot).

use std::path::PathBuf;

use pyo3::prelude::*;
use shapewright_usd::{load_file, LoadOptions, SaveOptions};

use crate::doc::Session;
use crate::error::ShapewrightError;

fn usd_err(path: &std::path::Path, e: impl std::fmt::Display) -> PyErr {
    ShapewrightError::new_err(format!("{}: {e}", path.display()))
}

/// Saves `doc` (ops, cursor, meshes) to `path` as usda, crash-safely
/// (temp file, fsync, rename).
#[pyfunction]
pub(crate) fn save_usd(py: Python<'_>, doc: &Session, path: PathBuf) -> PyResult<()> {
    let log = doc.log();
    py.detach(|| shapewright_usd::atomic::save_file(&path, log, &SaveOptions::default()))
        .map(|_| ())
        .map_err(|e| usd_err(&path, e))
}

/// Loads a session saved by `save_usd` (usda, usdc or usdz). With
/// `verify_history`, the whole history is replayed and compared with the
/// stored snapshot. Fails if the stored meshes disagree with the log.
#[pyfunction]
#[pyo3(signature = (path, verify_history=false))]
pub(crate) fn load_usd(py: Python<'_>, path: PathBuf, verify_history: bool) -> PyResult<Session> {
    let options = LoadOptions {
        verify_history,
        strict: true,
    };
    py.detach(|| load_file(&path, options))
        .map(|l| Session::from_log(l.log))
        .map_err(|e| usd_err(&path, e))
}
