//! USD save and load of a document with its op log, through
//! `shapewright-usd` (usda with the ops, the cursor and a snapshot): our
//! own files, and stages Blender's USD exporter wrote with the add-on's
//! export hook (the log under Blender's root prim, objects wherever
//! Blender put them).

use std::path::PathBuf;

use pyo3::prelude::*;
use shapewright_usd::{load_file, load_from_str, save_to_string, LoadOptions, Loaded, SaveOptions};

use crate::doc::Session;
use crate::error::ShapewrightError;

fn usd_err(what: &str, e: impl std::fmt::Display) -> PyErr {
    ShapewrightError::new_err(format!("{what}: {e}"))
}

fn with_report(l: Loaded) -> (Session, Vec<String>) {
    let report = l.report.mismatches.iter().map(|m| m.to_string()).collect();
    (Session::from_log(l.log), report)
}

/// Saves `doc` (ops, cursor, meshes) to `path` as usda, crash-safely
/// (temp file, fsync, rename).
#[pyfunction]
pub(crate) fn save_usd(py: Python<'_>, doc: &Session, path: PathBuf) -> PyResult<()> {
    let log = doc.log();
    py.detach(|| shapewright_usd::atomic::save_file(&path, log, &SaveOptions::default()))
        .map(|_| ())
        .map_err(|e| usd_err(&path.display().to_string(), e))
}

/// The usda text `save_usd` would write (the export hook copies its log
/// prim and parametric prims into the stage Blender exports).
#[pyfunction]
pub(crate) fn usd_text(py: Python<'_>, doc: &Session) -> PyResult<String> {
    let log = doc.log();
    py.detach(|| save_to_string(log, &SaveOptions::default()))
        .map_err(|e| usd_err("USD", e))
}

/// Loads a session saved by `save_usd` or by Blender's exporter with the
/// add-on's hook (usda, usdc or usdz). With `verify_history`, the whole
/// history is replayed and compared with the stored snapshot. With
/// `strict`, fails if the stored meshes or parametric prims disagree with
/// the log.
#[pyfunction]
#[pyo3(signature = (path, verify_history=false, strict=true))]
pub(crate) fn load_usd(
    py: Python<'_>,
    path: PathBuf,
    verify_history: bool,
    strict: bool,
) -> PyResult<Session> {
    let options = LoadOptions {
        verify_history,
        strict,
    };
    py.detach(|| load_file(&path, options))
        .map(|l| Session::from_log(l.log))
        .map_err(|e| usd_err(&path.display().to_string(), e))
}

/// Loads like `load_usd(path, strict=False)` and also returns what the
/// consistency check found (one line per mismatch; the log is the truth,
/// so an importer rebuilds the objects from it and reports these).
#[pyfunction]
pub(crate) fn import_usd(py: Python<'_>, path: PathBuf) -> PyResult<(Session, Vec<String>)> {
    let options = LoadOptions {
        verify_history: false,
        strict: false,
    };
    py.detach(|| load_file(&path, options))
        .map(with_report)
        .map_err(|e| usd_err(&path.display().to_string(), e))
}

/// [`import_usd`] for usda text (a stage with no file behind it).
#[pyfunction]
pub(crate) fn import_usd_text(py: Python<'_>, text: &str) -> PyResult<(Session, Vec<String>)> {
    let options = LoadOptions {
        verify_history: false,
        strict: false,
    };
    py.detach(|| load_from_str(text, options))
        .map(with_report)
        .map_err(|e| usd_err("USD text", e))
}
