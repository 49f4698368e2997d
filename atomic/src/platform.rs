//! What differs by operating system in a crash-safe write, and only that
//! (issue 32): putting the finished temporary file in the target's place
//! durably, and telling whether an open file is still the one at a path.
//!
//! **POSIX.** `rename(2)` replaces the target atomically; the rename is
//! made durable by `fsync` on the directory.
//!
//! **Windows.** `std::fs::rename` calls `MoveFileExW(from, to,
//! MOVEFILE_REPLACE_EXISTING)` (Rust's `library/std/src/sys/fs/windows.rs`),
//! which replaces atomically on NTFS but may return before the new
//! directory entry is on disk, and an application cannot fsync a directory
//! there (`FlushFileBuffers` needs a handle with write access, which a
//! directory does not give). So [`replace`] calls `MoveFileExW` itself
//! with `MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH`, which returns
//! only once the move is on disk, and [`sync_dir`] does nothing. A target
//! held open without delete sharing (an antivirus scan, another program)
//! makes the move fail with a sharing violation for a moment: it is retried
//! for about half a second before the write gives up (the target intact).
//! A read-only target is refused (`ERROR_ACCESS_DENIED`), as Windows
//! programs do, where POSIX replaces it.

use std::fs::File;
use std::io;
use std::path::Path;

/// Moves `from` over `to`, atomically and durably (see the module doc).
#[cfg(not(windows))]
pub(crate) fn replace(from: &Path, to: &Path) -> io::Result<()> {
    std::fs::rename(from, to)
}

/// Moves `from` over `to`, atomically and durably (see the module doc).
#[cfg(windows)]
pub(crate) fn replace(from: &Path, to: &Path) -> io::Result<()> {
    use windows_sys::Win32::Foundation::{
        ERROR_ACCESS_DENIED, ERROR_LOCK_VIOLATION, ERROR_SHARING_VIOLATION,
    };
    let mut wait = std::time::Duration::from_millis(20);
    for attempt in 0.. {
        match move_file_write_through(from, to) {
            Err(e)
                if attempt < 5
                    && [
                        ERROR_SHARING_VIOLATION,
                        ERROR_LOCK_VIOLATION,
                        ERROR_ACCESS_DENIED,
                    ]
                    .iter()
                    .any(|&c| e.raw_os_error() == Some(c as i32)) =>
            {
                std::thread::sleep(wait);
                wait *= 2;
            }
            other => return other,
        }
    }
    unreachable!("the loop returns")
}

/// One `MoveFileExW(from, to, REPLACE_EXISTING | WRITE_THROUGH)`.
#[cfg(windows)]
#[allow(unsafe_code)]
fn move_file_write_through(from: &Path, to: &Path) -> io::Result<()> {
    use std::os::windows::ffi::OsStrExt;
    use windows_sys::Win32::Storage::FileSystem::{
        MoveFileExW, MOVEFILE_REPLACE_EXISTING, MOVEFILE_WRITE_THROUGH,
    };
    let wide = |p: &Path| -> io::Result<Vec<u16>> {
        let w: Vec<u16> = p.as_os_str().encode_wide().chain([0]).collect();
        if w[..w.len() - 1].contains(&0) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "a path with a NUL character",
            ));
        }
        Ok(w)
    };
    let (from, to) = (wide(from)?, wide(to)?);
    // SAFETY: both are NUL-terminated UTF-16 strings without inner NULs
    // that live across the call; MoveFileExW only reads them.
    let ok = unsafe {
        MoveFileExW(
            from.as_ptr(),
            to.as_ptr(),
            MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH,
        )
    };
    if ok == 0 {
        Err(io::Error::last_os_error())
    } else {
        Ok(())
    }
}

/// Makes a rename in `dir` durable: `fsync` of the directory on POSIX;
/// nothing on Windows, where [`replace`] already waited for the disk.
pub(crate) fn sync_dir(dir: &Path) -> io::Result<()> {
    if cfg!(unix) {
        File::open(dir)?.sync_all()
    } else {
        Ok(())
    }
}

/// Whether the open `file` is still the file at `path` (not a file made
/// under the same name since): same device and inode on POSIX.
#[cfg(unix)]
pub(crate) fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Whether the open `file` is still the file at `path` (not a file made
/// under the same name since): std has no stable file id on Windows, so
/// the creation time (100 ns steps) and length stand for it; the
/// temporary names are unique per process, counter and time anyway.
#[cfg(not(unix))]
pub(crate) fn same_file(file: &File, path: &Path) -> bool {
    match (file.metadata(), std::fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => {
            a.is_file()
                && b.is_file()
                && a.len() == b.len()
                && matches!((a.created(), b.created()), (Ok(x), Ok(y)) if x == y)
        }
        _ => false,
    }
}
