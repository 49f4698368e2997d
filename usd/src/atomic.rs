//! Crash-safe saving and autosave.
//!
//! [`save_file`] writes the new content to a temporary file in the target's
//! directory, fsyncs it, renames it over the target (atomic on POSIX file
//! systems) and fsyncs the directory so the rename itself is durable. A
//! crash at any point leaves either the previous file or the new one, never
//! a mix; a stale temporary file may remain and is overwritten next time.
//!
//! [`Autosaver`] saves every [`AutosaveSettings::every_ops`] ops or once
//! [`AutosaveSettings::every`] has passed since the last save with unsaved
//! ops, whichever comes first.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use shapewright::doc::OpLog;

use crate::{save_to_string, SaveError, SaveOptions};

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> SaveError + '_ {
    move |source| SaveError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Writes `bytes` to `path` crash-safely (see the module doc).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), SaveError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| SaveError::Author(format!("{} names no file", path.display())))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = dir.join(tmp_name);
    let result = (|| {
        let mut f = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(&tmp)
            .map_err(io_err(&tmp))?;
        f.write_all(bytes).map_err(io_err(&tmp))?;
        f.sync_all().map_err(io_err(&tmp))?;
        drop(f);
        std::fs::rename(&tmp, path).map_err(io_err(path))?;
        // Make the rename durable. Opening a directory read-only and
        // fsyncing it is the POSIX way; other platforms skip it.
        #[cfg(unix)]
        File::open(&dir)
            .and_then(|d| d.sync_all())
            .map_err(io_err(&dir))?;
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Saves `log` to `path` as usda, crash-safely.
pub fn save_file(path: &Path, log: &OpLog, options: &SaveOptions) -> Result<(), SaveError> {
    let text = save_to_string(log, options)?;
    write_atomic(path, text.as_bytes())
}

/// When to autosave. Both triggers are active; set one very large to use
/// only the other.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AutosaveSettings {
    /// Save after this many ops (applied, undone or redone) since the last
    /// save. 1 saves after every op.
    pub every_ops: usize,
    /// Save when this long has passed since the last save and something
    /// changed.
    pub every: Duration,
}

impl Default for AutosaveSettings {
    fn default() -> Self {
        Self {
            every_ops: 1,
            every: Duration::from_secs(30),
        }
    }
}

/// Saves a log to a file when the settings say so.
#[derive(Debug)]
pub struct Autosaver {
    path: PathBuf,
    settings: AutosaveSettings,
    options: SaveOptions,
    changes: usize,
    last_save: Instant,
    saves: usize,
}

impl Autosaver {
    /// An autosaver for `path`.
    pub fn new(path: impl Into<PathBuf>, settings: AutosaveSettings, options: SaveOptions) -> Self {
        Self {
            path: path.into(),
            settings,
            options,
            changes: 0,
            last_save: Instant::now(),
            saves: 0,
        }
    }

    /// Call after each change of `log` (apply, undo, redo). Returns whether
    /// it saved.
    pub fn changed(&mut self, log: &OpLog) -> Result<bool, SaveError> {
        self.changes += 1;
        self.tick(log)
    }

    /// Call periodically (e.g. once per frame); saves when the time
    /// trigger fired and there are unsaved changes. Returns whether it saved.
    pub fn tick(&mut self, log: &OpLog) -> Result<bool, SaveError> {
        let due = self.changes >= self.settings.every_ops.max(1)
            || (self.changes > 0 && self.last_save.elapsed() >= self.settings.every);
        if due {
            self.save_now(log)?;
        }
        Ok(due)
    }

    /// Saves now, whatever the settings say.
    pub fn save_now(&mut self, log: &OpLog) -> Result<(), SaveError> {
        save_file(&self.path, log, &self.options)?;
        self.changes = 0;
        self.last_save = Instant::now();
        self.saves += 1;
        Ok(())
    }

    /// Changes not yet saved.
    pub fn unsaved_changes(&self) -> usize {
        self.changes
    }

    /// Number of saves done.
    pub fn saves(&self) -> usize {
        self.saves
    }
}
