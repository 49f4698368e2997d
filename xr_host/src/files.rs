//! Every file the host writes goes through here: crash-safe
//! (`shapewright_atomic`: temp file in the same directory, fsync, rename,
//! fsync the directory; temp files of interrupted writes removed by the
//! next write of the same target), so a kill or a full disk never leaves a
//! torn or empty STL, OBJ, PLY, PNG, trace or report where a good one was.

use std::io::Write;
use std::path::Path;

use anyhow::{bail, Context, Result};
use shapewright::mesh::{MeshFormat, PartNames, TriMesh, MESH_EXTENSIONS};
pub use shapewright_atomic::{interrupted_writes, StaleTemp, Written};

/// Writes `mesh` in the format named by `path`'s extension, crash-safely.
pub fn write_mesh(mesh: &TriMesh, path: &Path) -> Result<Written> {
    write_mesh_named(mesh, &PartNames::new(), path)
}

/// Writes `mesh` in the format named by `path`'s extension, crash-safely,
/// naming its parts (3MF objects) by `names` (the document's names by
/// object id, [`shapewright::doc::document_names`]).
pub fn write_mesh_named(mesh: &TriMesh, names: &PartNames, path: &Path) -> Result<Written> {
    let Some(format) = MeshFormat::from_path(path) else {
        bail!(
            "cannot write {}: unknown extension (use {MESH_EXTENSIONS})",
            path.display()
        );
    };
    shapewright_atomic::write_with(path, |w| format.write_named(mesh, names, w))
        .with_context(|| format!("writing {}", path.display()))
}

/// Writes `text` (a trace, a report, a brush) to `path`, crash-safely.
pub fn write_text(path: &Path, text: &str) -> Result<Written> {
    shapewright_atomic::write_with(path, |w| w.write_all(text.as_bytes()))
        .with_context(|| format!("writing {}", path.display()))
}

/// Reads a mesh in the format named by `path`'s extension, in metres
/// (each format's unit converted: STL and 3MF millimetres, OBJ and PLY
/// metres).
pub fn read_mesh(path: &Path) -> Result<TriMesh> {
    let Some(format) = MeshFormat::from_path(path) else {
        bail!(
            "cannot read {}: unknown extension (use {MESH_EXTENSIONS})",
            path.display()
        );
    };
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    format
        .read(&bytes)
        .with_context(|| format!("in {}", path.display()))
}

/// Lines saying that earlier writes of `path` were interrupted (their
/// temporary files are still there; the file holds the write before
/// them), or nothing.
pub fn interrupted_note(path: &Path) -> String {
    let Ok(stale) = interrupted_writes(path) else {
        return String::new();
    };
    stale
        .iter()
        .map(|t| {
            let age = t
                .modified
                .and_then(|m| m.elapsed().ok())
                .map_or(String::new(), |d| format!(", {} s ago", d.as_secs()));
            format!(
                "last save interrupted: {} ({} bytes{age}) was left by a save that did not finish; {} holds the save before it, and the next save removes the leftover\n",
                t.path.display(),
                t.len,
                path.display()
            )
        })
        .collect()
}
