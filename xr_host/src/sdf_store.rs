//! The on-disk cache of precomputed component SDFs: a directory of blobs
//! behind core's `SdfStore` (core does no file I/O). Blobs carry their own
//! version, key and checksum (`core::sdf::cache`), so a missing, truncated
//! or corrupt file just reads as a miss and is regenerated and rewritten.
//! Writes go to a temporary file renamed over the target, so a crash never
//! leaves a half-written blob under a valid name.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use shapewright::sdf::cache::{SdfCache, SdfStore};
use shapewright::sdf::volume::set_default_cache;

/// A directory of SDF blobs.
#[derive(Clone, Debug)]
pub struct DirStore {
    dir: PathBuf,
}

impl DirStore {
    /// A store in `dir` (created on first write).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into() }
    }

    /// The default directory: `$SHAPEWRIGHT_CACHE_DIR`, else
    /// `shapewright/sdf` in the user's cache directory
    /// ([`crate::xr::platform::cache_home`]).
    pub fn default_dir() -> Option<PathBuf> {
        if let Some(d) = std::env::var_os("SHAPEWRIGHT_CACHE_DIR") {
            return Some(PathBuf::from(d));
        }
        let base = crate::xr::platform::cache_home()?;
        Some(base.join("shapewright").join("sdf"))
    }

    /// A component cache backed by a store at the default directory (a
    /// memory-only cache when there is no such directory).
    pub fn default_cache() -> SdfCache {
        match Self::default_dir() {
            Some(dir) => SdfCache::with_store(Arc::new(Self::new(dir))),
            None => SdfCache::new(),
        }
    }

    /// Makes [`Self::default_cache`] the cache the core's document ops use
    /// (call once, at start-up, before any SDF op runs).
    pub fn install_default() {
        set_default_cache(Self::default_cache());
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn path(&self, key: &str) -> Option<PathBuf> {
        // Keys are file names made by core; refuse anything else.
        let ok = !key.is_empty()
            && key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c));
        (ok && !key.starts_with('.')).then(|| self.dir.join(key))
    }
}

impl SdfStore for DirStore {
    fn load(&self, key: &str) -> Option<Vec<u8>> {
        std::fs::read(self.path(key)?).ok()
    }

    fn store(&self, key: &str, bytes: &[u8]) {
        let Some(path) = self.path(key) else { return };
        let tmp = self.dir.join(format!(".{key}.{}.tmp", std::process::id()));
        let ok = std::fs::create_dir_all(&self.dir).is_ok()
            && std::fs::write(&tmp, bytes).is_ok()
            && std::fs::rename(&tmp, &path).is_ok();
        if !ok {
            let _ = std::fs::remove_file(&tmp);
        }
    }
}
