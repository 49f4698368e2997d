//! The core's autosave policy (`shapewright_usd::Autosaver`: after every
//! N changes, or once unsaved changes are T seconds old) for a host whose
//! UI must not wait for a save: the save itself runs on a thread of its
//! own, on a copy of the log (the copy shares the document's meshes), so a
//! big document's autosave costs the UI thread the copy, not the 500 MB
//! write. One save at a time; changes made meanwhile make the next one due.

use std::path::PathBuf;
use std::sync::Mutex;
use std::thread::JoinHandle;
use std::time::Duration;

use pyo3::prelude::*;
use shapewright_usd::{save_file, AutosaveSettings, SaveError, SaveOptions, SaveReport};

use crate::doc::Session;

type Running = (usize, JoinHandle<Result<SaveReport, SaveError>>);

/// Autosaves a session's log to one file, off the caller's thread.
#[pyclass(module = "shapewright._native")]
pub struct Autosaver {
    saver: shapewright_usd::Autosaver,
    running: Mutex<Option<Running>>,
    last_error: Option<String>,
}

impl Autosaver {
    /// Collects a finished save (success or failure).
    fn collect(&mut self, py: Python<'_>, wait: bool) {
        let mut running = self.running.lock().unwrap_or_else(|e| e.into_inner());
        let finished = running.as_ref().is_some_and(|(_, h)| h.is_finished());
        if !(finished || wait) {
            return;
        }
        let Some((covered, handle)) = running.take() else {
            return;
        };
        drop(running);
        let result = py
            .detach(|| handle.join())
            .unwrap_or_else(|_| Err(SaveError::Author("the autosave thread panicked".into())));
        self.last_error = result.as_ref().err().map(|e| e.to_string());
        self.saver.finish_save(covered, result);
    }

    /// Starts a save of `session` when one is due and none runs.
    fn start_if_due(&mut self, session: &Session) -> PyResult<bool> {
        let mut running = self.running.lock().unwrap_or_else(|e| e.into_inner());
        if running.is_some() || !self.saver.due() {
            return Ok(false);
        }
        let log = session.log().clone();
        let (path, options) = (
            self.saver.path().to_path_buf(),
            self.saver.options().clone(),
        );
        let covered = self.saver.begin_save();
        let handle = std::thread::Builder::new()
            .name("shapewright-autosave".into())
            .spawn(move || save_file(&path, &log, &options))
            .map_err(|e| crate::error::ShapewrightError::new_err(format!("autosave: {e}")))?;
        *running = Some((covered, handle));
        Ok(true)
    }
}

#[pymethods]
impl Autosaver {
    /// An autosaver writing `path` (usda), with the core's policy unless
    /// `every_ops` / `every_seconds` are given.
    #[new]
    #[pyo3(signature = (path, every_ops=None, every_seconds=None))]
    fn new(path: PathBuf, every_ops: Option<usize>, every_seconds: Option<f64>) -> Self {
        let d = AutosaveSettings::default();
        let settings = AutosaveSettings {
            every_ops: every_ops.unwrap_or(d.every_ops).max(1),
            every: every_seconds
                .filter(|s| s.is_finite() && *s >= 0.0)
                .map_or(d.every, Duration::from_secs_f64),
        };
        Self {
            saver: shapewright_usd::Autosaver::new(path, settings, SaveOptions::default()),
            running: Mutex::new(None),
            last_error: None,
        }
    }

    /// Counts one change of `session` (an op applied, undone or redone)
    /// and starts a save when the policy says so. Returns whether it
    /// started one. Costs the caller a copy of the log, never the write.
    fn changed(&mut self, py: Python<'_>, session: &Session) -> PyResult<bool> {
        self.collect(py, false);
        self.saver.note_change();
        self.start_if_due(session)
    }

    /// Call periodically: collects a finished save and starts one when
    /// unsaved changes are old enough. Returns whether it started one.
    fn tick(&mut self, py: Python<'_>, session: &Session) -> PyResult<bool> {
        self.collect(py, false);
        self.start_if_due(session)
    }

    /// Waits for a running save (before quitting, or in tests).
    fn wait(&mut self, py: Python<'_>) {
        self.collect(py, true);
    }

    /// True while a save runs.
    #[getter]
    fn busy(&self) -> bool {
        self.running
            .lock()
            .map(|r| r.as_ref().is_some_and(|(_, h)| !h.is_finished()))
            .unwrap_or(false)
    }

    /// Saves completed.
    #[getter]
    fn saves(&self) -> usize {
        self.saver.saves()
    }

    /// Changes not yet saved (a running save's count as saved).
    #[getter]
    fn unsaved_changes(&self) -> usize {
        self.saver.unsaved_changes()
    }

    /// Why the last save failed (None when it did not).
    #[getter]
    fn last_error(&self) -> Option<String> {
        self.last_error.clone()
    }

    /// The file it writes.
    #[getter]
    fn path(&self) -> PathBuf {
        self.saver.path().to_path_buf()
    }
}
