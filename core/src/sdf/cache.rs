//! On-disk cache of precomputed component SDFs (paper 2 §5.2 step 6 keeps
//! them as Unity assets; we keep them as versioned, checksummed blobs).
//!
//! **Where the I/O lives.** The core does no file I/O (ARCHITECTURE.md), so
//! the cache is split: this module encodes and verifies blobs, and a host
//! installs an [`SdfStore`] (a key → bytes store; a directory of files on
//! the desktop, anything else elsewhere) with [`install_store`]. Without a
//! store, SDFs are recomputed once per process and kept in memory.
//!
//! **Blob format** (little endian): magic `SWSDF\0\0\0`, format version
//! `u32`, cache key `u64`, dims `3 × u64`, origin `3 × f64`, step `f64`,
//! values `n × f32`, then a 64-bit [`ContentHasher`] checksum of all
//! preceding bytes. A blob with a wrong magic, version, key, length or
//! checksum is treated as missing: the SDF is recomputed and re-stored.

use std::sync::{Arc, RwLock};

use super::dense::DenseSdf;
use crate::hash::ContentHasher;

/// Version of the blob format and of the SDF computation; bump it when
/// either changes so that old blobs are regenerated.
pub const FORMAT_VERSION: u32 = 1;

const MAGIC: &[u8; 8] = b"SWSDF\0\0\0";

/// A key → bytes store for cached SDF blobs, provided by the host.
pub trait SdfStore: Send + Sync {
    /// The blob stored under `key`, if any.
    fn load(&self, key: &str) -> Option<Vec<u8>>;
    /// Stores `bytes` under `key` (errors are the store's to log; a failed
    /// store only costs a recomputation later).
    fn store(&self, key: &str, bytes: &[u8]);
}

fn slot() -> &'static RwLock<Option<Arc<dyn SdfStore>>> {
    static S: RwLock<Option<Arc<dyn SdfStore>>> = RwLock::new(None);
    &S
}

/// Installs (or, with `None`, removes) the process-wide store.
pub fn install_store(store: Option<Arc<dyn SdfStore>>) {
    if let Ok(mut s) = slot().write() {
        *s = store;
    }
}

/// The store key (a file name) of cache key `key`.
pub fn key_name(key: u64) -> String {
    format!("sdf-v{FORMAT_VERSION}-{key:016x}.bin")
}

fn checksum(bytes: &[u8]) -> u64 {
    let mut h = ContentHasher::new();
    h.bytes(bytes);
    h.finish()
}

/// Encodes `sdf` as a blob for cache key `key`.
pub fn encode(key: u64, sdf: &DenseSdf) -> Vec<u8> {
    let mut b = Vec::with_capacity(80 + sdf.values.len() * 4);
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    b.extend_from_slice(&key.to_le_bytes());
    for d in sdf.dims {
        b.extend_from_slice(&(d as u64).to_le_bytes());
    }
    for o in sdf.origin {
        b.extend_from_slice(&o.to_le_bytes());
    }
    b.extend_from_slice(&sdf.step.to_le_bytes());
    for v in &sdf.values {
        b.extend_from_slice(&v.to_le_bytes());
    }
    let c = checksum(&b);
    b.extend_from_slice(&c.to_le_bytes());
    b
}

struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Option<[u8; N]> {
        let (head, rest) = self.0.split_at_checked(N)?;
        self.0 = rest;
        head.try_into().ok()
    }
}

/// Decodes a blob, or `None` when it is corrupt, of another version or
/// for another key.
pub fn decode(key: u64, bytes: &[u8]) -> Option<DenseSdf> {
    let (body, tail) = bytes.split_at_checked(bytes.len().checked_sub(8)?)?;
    if checksum(body) != u64::from_le_bytes(tail.try_into().ok()?) {
        return None;
    }
    let mut r = Reader(body);
    if &r.take::<8>()? != MAGIC
        || u32::from_le_bytes(r.take()?) != FORMAT_VERSION
        || u64::from_le_bytes(r.take()?) != key
    {
        return None;
    }
    let mut dims = [0usize; 3];
    for d in &mut dims {
        *d = usize::try_from(u64::from_le_bytes(r.take()?)).ok()?;
        if *d < 2 {
            return None;
        }
    }
    let mut origin = [0.0; 3];
    for o in &mut origin {
        *o = f64::from_le_bytes(r.take()?);
    }
    let step = f64::from_le_bytes(r.take()?);
    let n = dims[0].checked_mul(dims[1])?.checked_mul(dims[2])?;
    if r.0.len() != n.checked_mul(4)? || !(step.is_finite() && step > 0.0) {
        return None;
    }
    let values: Vec<f32> =
        r.0.chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
    if values.iter().any(|v| !v.is_finite()) || origin.iter().any(|o| !o.is_finite()) {
        return None;
    }
    Some(DenseSdf {
        dims,
        origin,
        step,
        values,
    })
}

/// The SDF cached under `key` in the installed store, if present and valid.
pub fn load(key: u64) -> Option<DenseSdf> {
    let store = slot().read().ok()?.clone()?;
    decode(key, &store.load(&key_name(key))?)
}

/// Writes `sdf` to the installed store, if any.
pub fn store(key: u64, sdf: &DenseSdf) {
    let store = slot().read().ok().and_then(|s| s.clone());
    if let Some(s) = store {
        s.store(&key_name(key), &encode(key, sdf));
    }
}
