//! The USD file a save writes, by its extension (issue 31: every file
//! opens where its extension promises):
//! - `.usda` (and `.usd`, which Pixar USD reads by content): the usda text.
//! - `.usdz`: a USDZ package as Pixar's `UsdUtils` and Apple's AR Quick
//!   Look expect it: a zip whose first entry is the root layer (the usda,
//!   named after the file), stored uncompressed with its data aligned to
//!   64 bytes (openusd's `usdz::ArchiveWriter`, which writes exactly that
//!   with the `zip` crate).
//! - `.usdc` is refused, naming `.usda` and `.usdz`: openusd 0.6's crate
//!   writer is rejected by Pixar's reader ("Invalid children found in
//!   primChildren field"), and writing usda text under a `.usdc` name made
//!   a file Pixar refuses ("Sdf crate bootstrap section corrupt"). A
//!   crate writer of our own is a larger job than this format needs: usda
//!   holds the same layer and every USD tool reads it.
//!
//! Any other extension gets the usda text, as before (autosave names,
//! temporary files).

use std::io::Cursor;
use std::path::Path;

use crate::SaveError;

/// How a save encodes its layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UsdEncoding {
    /// usda text.
    Text,
    /// A USDZ package holding the usda text as its root layer.
    Package,
}

/// Every extension a save writes, as messages list them.
pub const SAVE_EXTENSIONS: &str = ".usda or .usdz";

impl UsdEncoding {
    /// The encoding for `path`, or [`SaveError::Unsupported`] for `.usdc`.
    pub fn of(path: &Path) -> Result<Self, SaveError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("usdz") => Ok(Self::Package),
            Some("usdc") => Err(SaveError::Unsupported {
                path: path.display().to_string(),
                why: format!(
                    "binary USD crate files (.usdc) are not written; save as {SAVE_EXTENSIONS} (the same layer, which Pixar USD and every USD tool open)"
                ),
            }),
            _ => Ok(Self::Text),
        }
    }

    /// The bytes of the file at `path` holding the usda `text`.
    pub fn encode(self, path: &Path, text: &str) -> Result<Vec<u8>, SaveError> {
        match self {
            Self::Text => Ok(text.as_bytes().to_vec()),
            Self::Package => package(path, text),
        }
    }
}

/// A USDZ package with `text` as its root layer `STEM.usda`.
fn package(path: &Path, text: &str) -> Result<Vec<u8>, SaveError> {
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty() && !s.contains(['/', '\\']) && *s != "..")
        .unwrap_or("root");
    let mut archive = openusd::usdz::ArchiveWriter::new(Cursor::new(Vec::new()));
    let author = |e: anyhow::Error| SaveError::Author(format!("usdz package: {e:#}"));
    archive
        .add_layer(&format!("{stem}.usda"), text.as_bytes())
        .map_err(author)?;
    Ok(archive.finish().map_err(author)?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn usdc_is_refused_naming_what_works() {
        let e = UsdEncoding::of(Path::new("a/model.USDC")).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains(".usda") && msg.contains(".usdz"), "{msg}");
        assert_eq!(
            UsdEncoding::of(Path::new("m.usdz")).unwrap(),
            UsdEncoding::Package
        );
        assert_eq!(
            UsdEncoding::of(Path::new("m.usda")).unwrap(),
            UsdEncoding::Text
        );
    }

    #[test]
    fn a_package_starts_with_its_root_layer_stored_and_aligned() {
        let text = "#usda 1.0\n(\n    defaultPrim = \"World\"\n)\n\ndef Xform \"World\"\n{\n}\n";
        let bytes = UsdEncoding::Package
            .encode(Path::new("dir/lamp.usdz"), text)
            .unwrap();
        // Local file header: signature, then method (offset 8) 0 = stored.
        assert_eq!(&bytes[..4], b"PK\x03\x04");
        assert_eq!(u16::from_le_bytes([bytes[8], bytes[9]]), 0);
        let name_len = u16::from_le_bytes([bytes[26], bytes[27]]) as usize;
        let extra_len = u16::from_le_bytes([bytes[28], bytes[29]]) as usize;
        assert_eq!(&bytes[30..30 + name_len], b"lamp.usda");
        let data = 30 + name_len + extra_len;
        assert_eq!(data % 64, 0, "data at {data}");
        assert_eq!(&bytes[data..data + text.len()], text.as_bytes());
    }
}
