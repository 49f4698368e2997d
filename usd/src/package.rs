//! The USD file a save writes, by its extension (issue 31: every file
//! opens where its extension promises):
//! - `.usda` (and `.usd`, which Pixar USD reads by content): the usda text.
//! - `.usdz`: a USDZ package as Pixar's `UsdUtils` and Apple's AR Quick
//!   Look expect it: a zip whose first entry is the root layer (the usda,
//!   named after the file), stored uncompressed with its data aligned to
//!   64 bytes. Written with the `zip` crate directly, as openusd's
//!   `usdz::ArchiveWriter` does, plus one option it lacks: every entry is
//!   "made by Unix". The zip crate otherwise records the system it was
//!   built for, so a Windows save differed from a Linux one in the central
//!   directory (issue 32: the same ops give the same bytes everywhere).
//! - `.usdc` is refused, naming `.usda` and `.usdz`: openusd 0.6's crate
//!   writer is rejected by Pixar's reader ("Invalid children found in
//!   primChildren field"), and writing usda text under a `.usdc` name made
//!   a file Pixar refuses ("Sdf crate bootstrap section corrupt"). A
//!   crate writer of our own is a larger job than this format needs: usda
//!   holds the same layer and every USD tool reads it.
//!
//! Any other extension gets the usda text, as before (autosave names,
//! temporary files).

use std::io::{Cursor, Write};
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
    let author = |e: &dyn std::fmt::Display| SaveError::Author(format!("usdz package: {e}"));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .with_alignment(USDZ_ALIGNMENT)
        .system(zip::System::Unix);
    let mut archive = zip::ZipWriter::new(Cursor::new(Vec::new()));
    archive
        .start_file(format!("{stem}.usda"), options)
        .map_err(|e| author(&e))?;
    archive.write_all(text.as_bytes()).map_err(|e| author(&e))?;
    Ok(archive.finish().map_err(|e| author(&e))?.into_inner())
}

/// USDZ's data alignment (Pixar's `UsdZipFileWriter`, openusd's writer).
const USDZ_ALIGNMENT: u16 = 64;

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
        // Central directory: "version made by" names Unix (3) in its high
        // byte on every platform (tests/windows compares whole files).
        let central = bytes
            .windows(4)
            .position(|w| w == b"PK\x01\x02")
            .expect("a central directory entry");
        assert_eq!(bytes[central + 5], 3, "made by Unix");
    }
}
