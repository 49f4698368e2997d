//! Crash-safe saving and autosave.
//!
//! [`save_file`] authors the layer ([`crate::author`]) and writes it with
//! the workspace's one crash-safe writer, [`shapewright_atomic::write_bytes`]:
//! a temporary file in the target's directory, fsync, rename, fsync of the
//! directory. A crash at any point leaves either the previous file or the
//! new one, never a mix; the temporary file a killed save leaves behind is
//! removed by the next save of the same target
//! ([`SaveReport::removed_stale`]).
//!
//! [`Autosaver`] saves every [`AutosaveSettings::every_ops`] ops or once
//! [`AutosaveSettings::every`] has passed since the last save with unsaved
//! ops, whichever comes first. The policy is the same for a host that
//! saves on another thread (Blender: a big document's save must not hold
//! the UI): [`Autosaver::note_change`] and [`Autosaver::due`] decide,
//! [`Autosaver::begin_save`] and [`Autosaver::finish_save`] bracket the
//! save it runs elsewhere.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use shapewright::doc::OpLog;

use crate::package::UsdEncoding;
use crate::{author, SaveError, SaveOptions, Unwritten};

/// What a save wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SaveReport {
    /// Bytes written.
    pub bytes: u64,
    /// Temporary files of earlier interrupted saves of the same file that
    /// this save removed.
    pub removed_stale: Vec<PathBuf>,
    /// Parametric parts that could not be written (everything else was).
    pub unwritten: Vec<Unwritten>,
}

impl SaveReport {
    /// One line per part left out, for a warning (empty when complete).
    pub fn warnings(&self) -> String {
        self.unwritten
            .iter()
            .map(|u| format!("not written: {u} (its mesh and the log are saved)\n"))
            .collect()
    }
}

/// Saves `log` to `path` crash-safely: usda text, or a USDZ package for
/// `.usdz`; `.usdc` is refused before anything is authored
/// ([`crate::package`]). Fails only when nothing could be written (the
/// previous file is then untouched); parts left out are listed in the
/// report.
pub fn save_file(path: &Path, log: &OpLog, options: &SaveOptions) -> Result<SaveReport, SaveError> {
    let encoding = UsdEncoding::of(path)?;
    let authored = author(log, options)?;
    let bytes = encoding.encode(path, &authored.text)?;
    let written = shapewright_atomic::write_bytes(path, &bytes)?;
    Ok(SaveReport {
        bytes: written.bytes,
        removed_stale: written.removed_stale,
        unwritten: authored.unwritten,
    })
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
    last_report: SaveReport,
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
            last_report: SaveReport::default(),
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
        let due = self.due();
        if due {
            self.save_now(log)?;
        }
        Ok(due)
    }

    /// Counts one change without saving (for a host that saves elsewhere;
    /// see [`Self::due`]).
    pub fn note_change(&mut self) {
        self.changes += 1;
    }

    /// Whether the settings say to save now: enough changes, or unsaved
    /// changes older than [`AutosaveSettings::every`].
    pub fn due(&self) -> bool {
        self.changes >= self.settings.every_ops.max(1)
            || (self.changes > 0 && self.last_save.elapsed() >= self.settings.every)
    }

    /// Starts a save that the host runs elsewhere (on another thread, with
    /// [`save_file`], [`Self::path`] and [`Self::options`]): the changes so
    /// far count as saved until [`Self::finish_save`] says otherwise.
    /// Returns how many changes the save covers.
    pub fn begin_save(&mut self) -> usize {
        let covered = self.changes;
        self.changes = 0;
        self.last_save = Instant::now();
        covered
    }

    /// Ends a save started by [`Self::begin_save`] covering `covered`
    /// changes: on success it counts as a save; on failure those changes
    /// are unsaved again (so the next [`Self::due`] retries).
    pub fn finish_save(&mut self, covered: usize, result: Result<SaveReport, SaveError>) {
        match result {
            Ok(report) => {
                self.last_report = report;
                self.saves += 1;
            }
            Err(_) => self.changes += covered,
        }
    }

    /// Where it saves.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// How it saves.
    pub fn options(&self) -> &SaveOptions {
        &self.options
    }

    /// When it saves.
    pub fn settings(&self) -> AutosaveSettings {
        self.settings
    }

    /// Saves now, whatever the settings say.
    pub fn save_now(&mut self, log: &OpLog) -> Result<(), SaveError> {
        self.last_report = save_file(&self.path, log, &self.options)?;
        self.changes = 0;
        self.last_save = Instant::now();
        self.saves += 1;
        Ok(())
    }

    /// What the last successful save wrote (which parts it left out).
    pub fn last_report(&self) -> &SaveReport {
        &self.last_report
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_save_run_elsewhere_follows_the_same_policy() {
        let dir = std::env::temp_dir().join(format!("sw-autosave-{}", std::process::id()));
        let settings = AutosaveSettings {
            every_ops: 3,
            every: Duration::from_secs(3600),
        };
        let mut saver = Autosaver::new(dir.join("a.usda"), settings, SaveOptions::default());
        saver.note_change();
        saver.note_change();
        assert!(!saver.due());
        saver.note_change();
        assert!(saver.due());
        let covered = saver.begin_save();
        assert_eq!((covered, saver.unsaved_changes()), (3, 0));
        assert!(!saver.due(), "a running save is not due again");
        saver.note_change();
        // The save failed: its changes are unsaved again, with the new one.
        saver.finish_save(covered, Err(SaveError::Author("disk full".into())));
        assert_eq!(saver.unsaved_changes(), 4);
        assert!(saver.due());
        let covered = saver.begin_save();
        saver.finish_save(covered, Ok(SaveReport::default()));
        assert_eq!((saver.saves(), saver.unsaved_changes()), (1, 0));
    }
}
