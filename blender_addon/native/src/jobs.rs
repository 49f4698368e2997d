//! Long work off Blender's UI thread. An [`ExportJob`] runs the core's one
//! print path (`shapewright::doc::print_document_with`) on a copy of the
//! document (meshes are shared, so the copy is cheap) on a thread of its
//! own and writes the result, while Blender keeps drawing; the same job
//! without a path is the History panel's printability check, so the panel
//! and the export can never disagree.
//!
//! Progress and cancelling are the core's [`PrintControl`]: the job's
//! progress moves through the union object by object, and
//! [`ExportJob::cancel`] stops it within one stage of one boolean (Manifold
//! checks the flag inside its booleans); a cancelled job writes nothing.
//! [`ExportJob::cancel`] returns at once, so Esc never waits for the
//! thread.
//!
//! Refusals write nothing: a model the print path refuses, a format the
//! path's extension does not name, a folder that does not exist (an
//! export never creates folders the person did not ask for). Files are
//! written to a temporary name and renamed, so a cancelled or failed
//! export never leaves half a file.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::thread::JoinHandle;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shapewright::doc::Document;
use shapewright::doc::{document_names, print_document_scaled, PrintScale, ScaledPrint};
use shapewright::mesh::{MeshFormat, PartNames, TriMesh, MESH_EXTENSIONS};
use shapewright::print::{
    BedFit, PrintControl, PrintError, PrintSettings, PrintStage, PrintedSize,
};

use crate::doc::Session;
use crate::error::{OpRejected, ParseError};

/// Why a job stopped.
#[derive(Debug)]
pub(crate) enum ExportError {
    /// The user cancelled; nothing was written.
    Cancelled,
    /// The result is not printable, or the path cannot be written to;
    /// nothing was written.
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

/// The mesh format of `path`, or a clear error.
pub(crate) fn format_of(path: &Path) -> PyResult<MeshFormat> {
    MeshFormat::from_path(path).ok_or_else(|| {
        ParseError::new_err(format!(
            "{}: unknown extension (use {MESH_EXTENSIONS}; STL and 3MF are written in millimetres for slicers, OBJ and PLY in metres)",
            path.display()
        ))
    })
}

/// Refuses a path whose folder does not exist (writing would create it).
fn check_folder(path: &Path) -> PyResult<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => return Ok(()),
    };
    if dir.is_dir() {
        Ok(())
    } else {
        Err(OpRejected::new_err(format!(
            "the folder {} does not exist; choose an existing folder (nothing was written)",
            dir.display()
        )))
    }
}

/// What a job found and, when it had a path, wrote.
pub(crate) struct Summary {
    triangles: usize,
    volume: f64,
    bbox: Option<[[f64; 3]; 2]>,
    report: String,
    size: Option<PrintedSize>,
    fit: Option<BedFit>,
    /// The factor it was printed at, and the sentence saying why when it
    /// was scaled to fit ([`ScaledPrint::scaled_line`]).
    scale: f64,
    scaled: Option<String>,
}

fn run(
    doc: &Document,
    target: Option<(MeshFormat, &Path)>,
    scale: PrintScale,
    control: &PrintControl,
) -> Result<Summary, ExportError> {
    // Without a file, the check is the STL export's (float32 millimetres,
    // as STL and 3MF store it): the panel says what the usual export will do.
    let settings = PrintSettings::for_format(target.map_or(MeshFormat::Stl, |(f, _)| f));
    let scaled = print_document_scaled(doc, &settings, scale, control).map_err(|e| match e {
        PrintError::Cancelled => ExportError::Cancelled,
        e if target.is_some() => ExportError::Refused(format!("{e}: nothing was written")),
        e => ExportError::Refused(e.to_string()),
    })?;
    let printed = &scaled.printable;
    if let Some((format, path)) = target {
        control.set(PrintStage::Writing, 0, 1);
        write_atomic(&printed.mesh, &document_names(doc), format, path, control)?;
    }
    control.set(PrintStage::Done, 1, 1);
    Ok(summary_of(doc, &scaled))
}

fn summary_of(doc: &Document, scaled: &ScaledPrint) -> Summary {
    let (mesh, report) = (&scaled.printable.mesh, &scaled.printable.report);
    let size = report.size();
    Summary {
        triangles: mesh.triangles.len(),
        volume: report.checks.signed_volume,
        bbox: report.checks.bbox,
        report: report.to_string(),
        size,
        fit: size.map(|s| s.fit(&doc.print_setup().printer)),
        scale: scaled.scale,
        scaled: scaled.scaled_line(),
    }
}

/// The scale an export asks for from Python: `fit=True` scales the model
/// down to the document's printer when it is too big; otherwise `scale`
/// (1: true size; 0.001 to 1000, refused by name outside that).
pub(crate) fn print_scale(scale: f64, fit: bool) -> PrintScale {
    if fit {
        PrintScale::ToFit
    } else {
        PrintScale::By(scale)
    }
}

/// Writes `mesh` to `path` crash-safely (the workspace's one writer:
/// temp file, fsync, rename); a cancel before the rename keeps the old file.
fn write_atomic(
    mesh: &TriMesh,
    names: &PartNames,
    format: MeshFormat,
    path: &Path,
    control: &PrintControl,
) -> Result<(), ExportError> {
    shapewright_atomic::write_with(path, |w| {
        format.write_named(mesh, names, w)?;
        if control.is_cancelled() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::Interrupted,
                "export cancelled",
            ));
        }
        Ok(())
    })
    .map(|_| ())
    .map_err(|e| {
        if control.is_cancelled() {
            ExportError::Cancelled
        } else {
            ExportError::Io(format!("writing {}: {e}", path.display()))
        }
    })
}

fn summary<'py>(py: Python<'py>, s: &Summary, path: Option<&Path>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("path", path.map(|p| p.display().to_string()))?;
    d.set_item("triangles", s.triangles)?;
    d.set_item("volume", s.volume)?;
    d.set_item("bbox", s.bbox)?;
    d.set_item("report", &s.report)?;
    d.set_item("scale", s.scale)?;
    d.set_item("scaled", s.scaled.as_deref())?;
    if let Some(size) = &s.size {
        d.set_item("size_mm", size.extent_mm().to_vec())?;
        d.set_item("volume_cm3", size.volume_cm3().unwrap_or(0.0))?;
    }
    if let Some(f) = &s.fit {
        d.set_item("fits", f.fits)?;
        d.set_item("fit", f.to_string())?;
        d.set_item("over_mm", f.over_mm.to_vec())?;
    }
    Ok(d)
}

/// Exports `doc`'s printable union to `path` on the calling thread (GIL
/// released), with the same checks as [`ExportJob`].
pub(crate) fn export_now<'py>(
    py: Python<'py>,
    doc: &Document,
    path: &Path,
    scale: PrintScale,
) -> PyResult<Bound<'py, PyDict>> {
    let format = format_of(path)?;
    check_folder(path)?;
    let control = PrintControl::new();
    let s = py
        .detach(|| run(doc, Some((format, path)), scale, &control))
        .map_err(ExportError::into_py)?;
    summary(py, &s, Some(path))
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
    let Some(status) = py.detach(|| shapewright::doc::print_status(doc)) else {
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

/// A print job running on its own thread: an export (with a path) or the
/// printability check (without).
#[pyclass(module = "shapewright._native")]
pub struct ExportJob {
    control: PrintControl,
    path: Option<PathBuf>,
    handle: Mutex<Option<JoinHandle<Result<Summary, ExportError>>>>,
}

#[pymethods]
impl ExportJob {
    /// Starts printing `doc` as it is now (later edits do not change this
    /// job): to `path` (format by extension) or, without a path, only the
    /// check the export would make; at `scale` (1: true size), or with
    /// `fit=True` scaled down to the document's printer when too big.
    #[new]
    #[pyo3(signature = (doc, path=None, *, scale=1.0, fit=false))]
    fn new(doc: &Session, path: Option<PathBuf>, scale: f64, fit: bool) -> PyResult<Self> {
        let scale = print_scale(scale, fit);
        let format = path.as_deref().map(format_of).transpose()?;
        if let Some(p) = &path {
            check_folder(p)?;
        }
        let document = doc.log().document().clone();
        let control = PrintControl::new();
        let (c, p) = (control.clone(), path.clone());
        let handle = std::thread::Builder::new()
            .name("shapewright-print".into())
            .spawn(move || {
                let target = format.zip(p.as_deref());
                run(&document, target, scale, &c)
            })
            .map_err(|e| OpRejected::new_err(format!("cannot start the print thread: {e}")))?;
        Ok(Self {
            control,
            path,
            handle: Mutex::new(Some(handle)),
        })
    }

    /// `(stage, fraction)`: what the job does now and how far it is.
    fn progress(&self) -> (&'static str, f64) {
        let p = self.control.progress();
        (p.stage.name(), p.fraction())
    }

    /// Asks the job to stop; returns at once. Nothing is written once it
    /// stops (within one stage of one boolean).
    fn cancel(&self) {
        self.control.cancel();
    }

    /// True when the thread has finished (successfully or not).
    fn done(&self) -> bool {
        self.handle
            .lock()
            .map(|h| h.as_ref().is_none_or(JoinHandle::is_finished))
            .unwrap_or(true)
    }

    /// Waits for the job and returns `{"path", "triangles", "volume",
    /// "bbox", "report"}` (metres; `path` None for a check), `"scale"` (the
    /// factor printed at) and `"scaled"` (the sentence saying so when the
    /// model was scaled to fit, else None), and the printed
    /// size: `"size_mm"`, `"volume_cm3"`, `"fits"`, `"fit"` (the sentence
    /// to show), `"over_mm"`; or raises
    /// why nothing was written. Call once.
    fn result<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let handle = self
            .handle
            .lock()
            .ok()
            .and_then(|mut h| h.take())
            .ok_or_else(|| OpRejected::new_err("the job's result was already taken"))?;
        let out = py
            .detach(|| handle.join())
            .map_err(|_| OpRejected::new_err("the print thread panicked; nothing was written"))?;
        let s = out.map_err(ExportError::into_py)?;
        summary(py, &s, self.path.as_deref())
    }
}
