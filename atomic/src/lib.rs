//! Crash-safe file writes for every Shapewright writer (issue 22, "atomic
//! writes for every format").
//!
//! [`write_with`] (and [`write_bytes`]) write a file so that a crash, a
//! `kill -9` or a full disk at any moment leaves the target either as it
//! was before or as the complete new file, never empty or torn:
//!
//! 1. the content goes to a temporary file in the target's own directory
//!    (same file system, so the rename below is atomic), named
//!    `.<name>.<pid>-<n>-<nanos>.swtmp`, created exclusively and locked
//!    (`flock`, exclusive; `LockFileEx` on Windows) for as long as the
//!    writer holds it;
//! 2. the temporary file is flushed and `fsync`ed (`FlushFileBuffers`);
//! 3. it is renamed over the target (atomic on POSIX file systems and NTFS);
//! 4. the rename is made durable: the directory is `fsync`ed on POSIX; on
//!    Windows the rename itself waits for the disk
//!    (`MOVEFILE_WRITE_THROUGH`; see `platform.rs`).
//!
//! A writer killed between 1 and 3 leaves its temporary file behind. The
//! next write of the same target removes every such file that no live
//! writer holds: a crashed writer's lock is released by the kernel when
//! the process dies, so a temporary file that can be locked belongs to
//! nobody. A file still locked belongs to a writer at work (another thread
//! or process saving the same target) and is left alone. Before removing,
//! the cleaner checks that the file it locked is still the one at that name
//! (same inode), so it never removes a file a writer created in between.
//! [`interrupted_writes`] lists the abandoned temporary files without
//! removing them, so that `info` can say the last save was interrupted.
//!
//! Where this lives: `core` does no I/O (ARCHITECTURE.md), and `usd` is the
//! USD mapping; putting the helper there would make the PNG, trace and
//! report writers of the hosts depend on `openusd`. This small crate has no
//! dependency but `thiserror`, so `usd`, `xr_host` and the pyo3 crate all
//! use the one helper.
//!
//! Choices: the content is streamed through a `BufWriter` (a big mesh is
//! not copied into one buffer first); the parent directory is created when
//! missing; an existing target's permissions are carried over to the new
//! file. A symbolic link at the target is replaced by the file, not
//! followed (rename semantics).
//!
//! What differs by OS lives in `platform.rs`: the durable replace, the
//! directory sync and the file identity check. Its one `unsafe` call
//! (`MoveFileExW`, Windows only) is the only one in this crate.
#![deny(unsafe_code)]

mod platform;
#[cfg(feature = "testkit")]
pub mod testkit;

use platform::{replace, same_file, sync_dir};

use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

/// Suffix of every temporary file this crate makes.
pub const TEMP_SUFFIX: &str = ".swtmp";

/// Why a file could not be written. The target is untouched in every case.
#[derive(Debug, thiserror::Error)]
pub enum AtomicError {
    /// The path names no file (it is empty, a root, or ends in `..`).
    #[error("{path} names no file to write (give a file name)")]
    NoFileName {
        /// The path as given.
        path: String,
    },
    /// Creating the directory or the temporary file, writing the content,
    /// syncing, or renaming failed (disk full, no permission, ...).
    #[error("{action} {path}: {source}")]
    Io {
        /// What was being done (`creating`, `writing`, `syncing`, `renaming to`).
        action: &'static str,
        /// The file or directory concerned.
        path: String,
        /// The OS error (or the content writer's error).
        source: io::Error,
    },
}

/// What a write did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Written {
    /// Bytes written.
    pub bytes: u64,
    /// Temporary files of earlier, interrupted writes of the same target
    /// that this write removed.
    pub removed_stale: Vec<PathBuf>,
}

/// A temporary file left by an interrupted write.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StaleTemp {
    /// Its path.
    pub path: PathBuf,
    /// Its size in bytes (what the interrupted write had written).
    pub len: u64,
    /// When it was last written.
    pub modified: Option<SystemTime>,
}

fn io_err<'a>(action: &'static str, path: &'a Path) -> impl FnOnce(io::Error) -> AtomicError + 'a {
    move |source| AtomicError::Io {
        action,
        path: path.display().to_string(),
        source,
    }
}

/// The directory and file name of `path`.
fn split(path: &Path) -> Result<(PathBuf, String), AtomicError> {
    let no_name = || AtomicError::NoFileName {
        path: path.display().to_string(),
    };
    let name = path.file_name().ok_or_else(no_name)?;
    let name = name.to_string_lossy().into_owned();
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok((dir, name))
}

/// True when `file_name` is a temporary file of target `name`.
fn is_temp_of(file_name: &str, name: &str) -> bool {
    file_name
        .strip_prefix('.')
        .and_then(|r| r.strip_prefix(name))
        .and_then(|r| r.strip_prefix('.'))
        .and_then(|r| r.strip_suffix(TEMP_SUFFIX))
        .is_some_and(|tag| !tag.is_empty() && !tag.contains('.') && !tag.contains('/'))
}

/// The temporary files of target `path` now in its directory (locked or not).
fn temp_files(path: &Path) -> Result<Vec<PathBuf>, AtomicError> {
    let (dir, name) = split(path)?;
    let entries = match std::fs::read_dir(&dir) {
        Ok(e) => e,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io_err("listing", &dir)(e)),
    };
    let mut out: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .filter(|e| is_temp_of(&e.file_name().to_string_lossy(), &name))
        .map(|e| e.path())
        .collect();
    out.sort();
    Ok(out)
}

/// Opens the temporary file at `p` and locks it when no live writer holds
/// it. `None` when it is held, gone, or unreadable.
fn lock_abandoned(p: &Path) -> Option<File> {
    let f = File::open(p).ok()?;
    f.try_lock().ok()?;
    same_file(&f, p).then_some(f)
}

/// Temporary files of earlier writes of `path` that were interrupted (their
/// writer died before renaming them), without removing them.
pub fn interrupted_writes(path: &Path) -> Result<Vec<StaleTemp>, AtomicError> {
    let mut out = Vec::new();
    for p in temp_files(path)? {
        let Some(f) = lock_abandoned(&p) else {
            continue;
        };
        let meta = f.metadata().ok();
        out.push(StaleTemp {
            len: meta.as_ref().map_or(0, |m| m.len()),
            modified: meta.and_then(|m| m.modified().ok()),
            path: p,
        });
    }
    Ok(out)
}

/// Removes the temporary files that interrupted writes of `path` left
/// behind (those no live writer holds) and returns them.
pub fn remove_stale(path: &Path) -> Result<Vec<PathBuf>, AtomicError> {
    let mut removed = Vec::new();
    for p in temp_files(path)? {
        // Hold the lock while unlinking, so a writer cannot be handed the
        // same file in between.
        let Some(lock) = lock_abandoned(&p) else {
            continue;
        };
        if std::fs::remove_file(&p).is_ok() {
            removed.push(p);
        }
        drop(lock);
    }
    Ok(removed)
}

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Creates, locks and returns a fresh temporary file for target `name` in `dir`.
fn create_temp(dir: &Path, name: &str) -> Result<(PathBuf, File), AtomicError> {
    let mut last = None;
    for _ in 0..16 {
        let nanos = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(
            ".{name}.{}-{n}-{nanos}{TEMP_SUFFIX}",
            std::process::id()
        ));
        let f = match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => f,
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                last = Some(e);
                continue;
            }
            Err(e) => return Err(io_err("creating", &tmp)(e)),
        };
        if let Err(e) = f.try_lock() {
            last = Some(io::Error::other(e.to_string()));
            continue;
        }
        // A cleaner may have removed the file between create and lock (it
        // could lock it then); start over with a new name if so.
        if !same_file(&f, &tmp) {
            last = Some(io::Error::other("temporary file removed while opening"));
            continue;
        }
        return Ok((tmp, f));
    }
    let err = last.unwrap_or_else(|| io::Error::other("no free temporary name"));
    Err(io_err("creating a temporary file in", dir)(err))
}

/// Writes the file at `path` crash-safely (see the crate doc) with the
/// content that `content` writes to the buffered writer it is given.
///
/// On any error (also one returned by `content`) the temporary file is
/// removed and the target keeps its previous content.
pub fn write_with<F>(path: &Path, content: F) -> Result<Written, AtomicError>
where
    F: FnOnce(&mut BufWriter<File>) -> io::Result<()>,
{
    let (dir, name) = split(path)?;
    std::fs::create_dir_all(&dir).map_err(io_err("creating", &dir))?;
    let removed_stale = remove_stale(path)?;
    let (tmp, file) = create_temp(&dir, &name)?;
    let result = (|| {
        if let Ok(meta) = std::fs::metadata(path) {
            // Keep the target's permissions (best effort).
            let _ = file.set_permissions(meta.permissions());
        }
        let lock = file.try_clone().map_err(io_err("creating", &tmp))?;
        let mut w = BufWriter::with_capacity(1 << 16, file);
        content(&mut w).map_err(io_err("writing", &tmp))?;
        let file = w
            .into_inner()
            .map_err(|e| io_err("writing", &tmp)(e.into_error()))?;
        file.sync_all().map_err(io_err("syncing", &tmp))?;
        let bytes = file.metadata().map_or(0, |m| m.len());
        drop(file);
        // The lock (on `lock`, the same open file) is held through the
        // rename, so no cleaner takes the file while it is still ours.
        replace(&tmp, path).map_err(io_err("renaming to", path))?;
        drop(lock);
        // Make the rename durable (POSIX: fsync the directory).
        sync_dir(&dir).map_err(io_err("syncing", &dir))?;
        Ok(bytes)
    })();
    match result {
        Ok(bytes) => Ok(Written {
            bytes,
            removed_stale,
        }),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Writes `bytes` to `path` crash-safely.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<Written, AtomicError> {
    write_with(path, |w| w.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("sw-atomic-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn writes_replaces_and_leaves_no_temp() {
        let d = scratch("basic");
        let p = d.join("a.stl");
        write_bytes(&p, b"one").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        let w = write_bytes(&p, b"second").unwrap();
        assert_eq!(w.bytes, 6);
        assert!(w.removed_stale.is_empty());
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        let names: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("a.stl")]);
    }

    #[test]
    fn failing_content_keeps_the_old_file() {
        let d = scratch("fail");
        let p = d.join("a.obj");
        write_bytes(&p, b"old").unwrap();
        let err = write_with(&p, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("encoder failed"))
        })
        .unwrap_err();
        assert!(err.to_string().contains("encoder failed"), "{err}");
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert_eq!(temp_files(&p).unwrap(), Vec::<PathBuf>::new());
    }

    #[test]
    fn stale_temps_are_reported_then_removed_but_live_ones_kept() {
        let d = scratch("stale");
        let p = d.join("m.ply");
        write_bytes(&p, b"good").unwrap();
        // An abandoned temp (as a killed writer leaves it) and one a live
        // writer holds.
        let dead = d.join(format!(".m.ply.1-0-0{TEMP_SUFFIX}"));
        std::fs::write(&dead, b"torn").unwrap();
        let (live, held) = create_temp(&d, "m.ply").unwrap();
        // Temps of other targets are not ours.
        let other = d.join(format!(".m.ply.bak.1-0-0{TEMP_SUFFIX}"));
        std::fs::write(&other, b"x").unwrap();
        let found = interrupted_writes(&p).unwrap();
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].path, dead);
        assert_eq!(found[0].len, 4);
        let w = write_bytes(&p, b"new").unwrap();
        assert_eq!(w.removed_stale, vec![dead.clone()]);
        assert!(!dead.exists());
        assert!(live.exists(), "a temp held by a live writer must stay");
        assert!(other.exists());
        drop(held);
        assert_eq!(interrupted_writes(&p).unwrap().len(), 1);
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
    }

    #[test]
    fn names_and_directories() {
        let d = scratch("dirs");
        let p = d.join("sub/deeper/x.usda");
        write_bytes(&p, b"x").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"x");
        assert!(matches!(
            write_bytes(Path::new("/"), b"x"),
            Err(AtomicError::NoFileName { .. })
        ));
        assert!(is_temp_of(".a.stl.12-3-4.swtmp", "a.stl"));
        assert!(!is_temp_of(".a.stl.swtmp", "a.stl"));
        assert!(!is_temp_of(".a.stl.x.y.swtmp", "a.stl"));
        assert!(!is_temp_of(".b.stl.1.swtmp", "a.stl"));
    }

    #[cfg(unix)]
    #[test]
    fn permissions_are_kept() {
        use std::os::unix::fs::PermissionsExt;
        let d = scratch("perm");
        let p = d.join("r.json");
        write_bytes(&p, b"1").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_bytes(&p, b"2").unwrap();
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600);
    }
}
