//! Long work off Blender's UI thread (issue 20 "long work off the UI
//! thread"). An [`ExportJob`] unions a copy of the document (meshes are
//! shared, so the copy is cheap) on a thread of its own, checks it and
//! writes it, while Blender keeps drawing; the add-on's modal operator
//! polls [`ExportJob::progress`] for Blender's progress bar and calls
//! [`ExportJob::cancel`] on Esc.
//!
//! The export is refused, and nothing is written, when the printable
//! model is empty or is not a closed 2-manifold at the precision the
//! format stores (STL and PLY store f32: triangles that collapse when
//! rounded are caught here). Files are written to a temporary name and
//! renamed, so a cancelled or failed export never leaves half a file.
//! Cancelling is checked between the phases (union, check, write): the
//! union itself is one Manifold batch boolean with no cancellation point,
//! so a cancel during it returns at once to the user but the thread
//! finishes that boolean before it stops (its result is dropped).
//!
//! The union is `Document::printable_mesh`; the printability work of
//! issue 19 (`core::print`, thickening and repair at the written
//! precision) will replace [`printable`]'s body when it lands.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shapewright::doc::Document;
use shapewright::mesh::{MeshFormat, PartNames, TriMesh, MESH_EXTENSIONS};
use shapewright::print::{document_names, print_document, BedFit, PrintSettings, PrintedSize};

use crate::doc::Session;
use crate::error::{OpRejected, ParseError};

/// Why an export stopped.
#[derive(Debug)]
pub(crate) enum ExportError {
    /// The user cancelled; nothing was written.
    Cancelled,
    /// The result is not printable; nothing was written.
    Refused(String),
    /// Writing failed.
    Io(String),
}

impl ExportError {
    fn into_py(self) -> PyErr {
        match self {
            Self::Cancelled => OpRejected::new_err("export cancelled; nothing was written"),
            Self::Refused(m) => OpRejected::new_err(m),
            Self::Io(m) => pyo3::exceptions::PyOSError::new_err(m),
        }
    }
}

/// The phases of an export, in order.
pub(crate) const PHASES: [(&str, f64); 4] = [
    ("uniting objects", 0.0),
    ("checking the result", 0.85),
    ("writing", 0.93),
    ("done", 1.0),
];

/// The mesh format of `path`, or a clear error.
pub(crate) fn format_of(path: &Path) -> PyResult<MeshFormat> {
    MeshFormat::from_path(path).ok_or_else(|| {
        ParseError::new_err(format!(
            "{}: unknown extension (use {MESH_EXTENSIONS}; STL and 3MF are written in millimetres for slicers, OBJ and PLY in metres)",
            path.display()
        ))
    })
}

/// The printable model of `doc` as `format` writes it: the core's one
/// printable path (union of every object, open surfaces thickened,
/// validated at the file's precision and unit), refused with the core's
/// typed reason (empty, out of range, not a closed 2-manifold when
/// written), with its printed size.
pub(crate) fn printable(
    doc: &Document,
    format: MeshFormat,
    phase: &AtomicU8,
    cancel: &AtomicBool,
) -> Result<(TriMesh, Option<PrintedSize>), ExportError> {
    let settings = PrintSettings::for_format(format);
    let printed = print_document(doc, &settings)
        .map_err(|e| ExportError::Refused(format!("{e}: nothing was written")))?;
    phase.store(1, Ordering::Relaxed);
    if cancel.load(Ordering::Relaxed) {
        return Err(ExportError::Cancelled);
    }
    let size = printed.report.size();
    Ok((printed.mesh, size))
}

/// Writes `mesh` to `path` crash-safely (the workspace's one writer:
/// temp file, fsync, rename); a cancel before the rename keeps the old file.
pub(crate) fn write_atomic(
    mesh: &TriMesh,
    names: &PartNames,
    format: MeshFormat,
    path: &Path,
    cancel: &AtomicBool,
) -> Result<(), ExportError> {
    shapewright_atomic::write_with(path, |w| {
        format.write_named(mesh, names, w)?;
        if cancel.load(Ordering::Relaxed) {
            return Err(std::io::Error::new(
                std::io::ErrorKind::Interrupted,
                "export cancelled",
            ));
        }
        Ok(())
    })
    .map(|_| ())
    .map_err(|e| {
        if cancel.load(Ordering::Relaxed) {
            ExportError::Cancelled
        } else {
            ExportError::Io(format!("writing {}: {e}", path.display()))
        }
    })
}

/// What a finished export wrote.
pub(crate) struct Written {
    triangles: usize,
    size: Option<PrintedSize>,
    fit: Option<BedFit>,
}

fn run(
    doc: &Document,
    format: MeshFormat,
    path: &Path,
    phase: &AtomicU8,
    cancel: &AtomicBool,
) -> Result<Written, ExportError> {
    let (mesh, size) = printable(doc, format, phase, cancel)?;
    phase.store(2, Ordering::Relaxed);
    write_atomic(&mesh, &document_names(doc), format, path, cancel)?;
    phase.store(3, Ordering::Relaxed);
    Ok(Written {
        triangles: mesh.triangles.len(),
        size,
        fit: size.map(|s| s.fit(&doc.print_setup().printer)),
    })
}

/// `{"path", "triangles", "volume" (m³), "size_mm" [x, y, z],
/// "volume_cm3", "fits", "fit" (the sentence to show: fits the printer,
/// or by how much it outgrows it per axis), "over_mm" [x, y, z]}`.
fn summary<'py>(py: Python<'py>, w: &Written, path: &Path) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("path", path.display().to_string())?;
    d.set_item("triangles", w.triangles)?;
    d.set_item("volume", w.size.and_then(|s| s.volume).unwrap_or(0.0))?;
    if let Some(s) = &w.size {
        d.set_item("size_mm", s.extent_mm().to_vec())?;
        d.set_item("volume_cm3", s.volume_cm3().unwrap_or(0.0))?;
    }
    if let Some(f) = &w.fit {
        d.set_item("fits", f.fits)?;
        d.set_item("fit", f.to_string())?;
        d.set_item("over_mm", f.over_mm.to_vec())?;
    }
    Ok(d)
}

/// `{"line", "warn", "size_mm" [x, y, z], "fits", "over_mm" [x, y, z],
/// "printer", "printer_size_mm" [x, y, z]}` for the History panel: the
/// core's print status (the objects' bounding box, no union, so it is
/// cheap after every edit) against the document's printer; `line` is the
/// text to show (`print 120 x 80 x 95 mm, fits Prusa MK4`, or `... too
/// big for Prusa MK4 by x 100.0 mm`), `warn` says to show it as a
/// warning. None for a document with nothing to print.
pub(crate) fn print_status_dict<'py>(
    py: Python<'py>,
    doc: &Document,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(status) = py.detach(|| shapewright::print::print_status(doc)) else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    d.set_item("line", status.line())?;
    d.set_item("warn", status.warn())?;
    d.set_item("size_mm", status.size.extent_mm().to_vec())?;
    d.set_item("fits", status.fit.fits)?;
    d.set_item("over_mm", status.fit.over_mm.to_vec())?;
    d.set_item("printer", status.fit.printer.preset.label())?;
    d.set_item(
        "printer_size_mm",
        status.fit.printer.size.map(|v| v * 1e3).to_vec(),
    )?;
    Ok(Some(d))
}

/// Exports `doc`'s printable union to `path` on the calling thread (GIL
/// released), with the same checks as [`ExportJob`].
pub(crate) fn export_now<'py>(
    py: Python<'py>,
    doc: &Document,
    path: &Path,
) -> PyResult<Bound<'py, PyDict>> {
    let format = format_of(path)?;
    let (phase, cancel) = (AtomicU8::new(0), AtomicBool::new(false));
    let w = py
        .detach(|| run(doc, format, path, &phase, &cancel))
        .map_err(ExportError::into_py)?;
    summary(py, &w, path)
}

struct Shared {
    phase: AtomicU8,
    cancel: AtomicBool,
}

/// An export running on its own thread.
#[pyclass(module = "shapewright._native")]
pub struct ExportJob {
    shared: Arc<Shared>,
    path: PathBuf,
    handle: Mutex<Option<JoinHandle<Result<Written, ExportError>>>>,
}

#[pymethods]
impl ExportJob {
    /// Starts exporting `doc`'s printable union (as it is now; later edits
    /// do not change this export) to `path` (.stl or .3mf in millimetres,
    /// .obj or .ply in metres).
    #[new]
    fn new(doc: &Session, path: PathBuf) -> PyResult<Self> {
        let format = format_of(&path)?;
        let document = doc.log().document().clone();
        let shared = Arc::new(Shared {
            phase: AtomicU8::new(0),
            cancel: AtomicBool::new(false),
        });
        let (s, p) = (Arc::clone(&shared), path.clone());
        let handle = std::thread::Builder::new()
            .name("shapewright-export".into())
            .spawn(move || run(&document, format, &p, &s.phase, &s.cancel))
            .map_err(|e| OpRejected::new_err(format!("cannot start the export thread: {e}")))?;
        Ok(Self {
            shared,
            path,
            handle: Mutex::new(Some(handle)),
        })
    }

    /// `(phase, fraction)`: what the job does now and how far it is.
    fn progress(&self) -> (&'static str, f64) {
        let i = usize::from(self.shared.phase.load(Ordering::Relaxed)).min(PHASES.len() - 1);
        PHASES[i]
    }

    /// Asks the job to stop; nothing is written once it stops.
    fn cancel(&self) {
        self.shared.cancel.store(true, Ordering::Relaxed);
    }

    /// True when the thread has finished (successfully or not).
    fn done(&self) -> bool {
        self.handle
            .lock()
            .map(|h| h.as_ref().is_none_or(JoinHandle::is_finished))
            .unwrap_or(true)
    }

    /// Waits for the job and returns `{"path", "triangles", "volume"}`, or
    /// raises why nothing was written. Call once.
    fn result<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let handle = self
            .handle
            .lock()
            .ok()
            .and_then(|mut h| h.take())
            .ok_or_else(|| OpRejected::new_err("the export's result was already taken"))?;
        let out = py
            .detach(|| handle.join())
            .map_err(|_| OpRejected::new_err("the export thread panicked; nothing was written"))?;
        let w = out.map_err(ExportError::into_py)?;
        summary(py, &w, &self.path)
    }
}
