//! The cache of precomputed component SDFs, as a value the host owns and
//! passes in: [`SdfCache`] (paper 2 §5.2 step 6 keeps them as Unity
//! assets; we keep them in memory and, when the host gives a store, as
//! versioned, checksummed blobs).
//!
//! **Where the I/O lives.** The core does no file I/O (ARCHITECTURE.md).
//! A host that wants SDFs to survive the process builds its cache with
//! [`SdfCache::with_store`] around an [`SdfStore`] (a key → bytes store;
//! a directory of files on the desktop, anything else elsewhere) and hands
//! that cache to whatever builds volumes. There is no process-wide store:
//! two caches (two documents, two hosts in one test) never see each
//! other's entries. Entries depend only on the mesh bits and the format
//! version, so a hit and a recomputation give the same bits.
//!
//! **Blob format** (little endian): magic `SWSDF\0\0\0`, format version
//! `u32`, cache key `u64`, dims `3 × u64`, origin `3 × f64`, step `f64`,
//! values `n × f32`, then a 64-bit [`ContentHasher`] checksum of all
//! preceding bytes. A blob with a wrong magic, version, key, length or
//! checksum is treated as missing: the SDF is recomputed and re-stored.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use super::dense::{DenseSdf, GridField};
use super::library;
use super::mesh_sdf::{component_sdf, component_sdf_at};
use super::SdfError;
use crate::hash::ContentHasher;
use crate::mesh::TriMesh;

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

/// Component SDFs computed so far (by mesh key and by library name), and
/// the host's persistent store if it gave one. Cloning shares the cache.
#[derive(Clone, Default)]
pub struct SdfCache {
    inner: Arc<Inner>,
}

#[derive(Default)]
struct Inner {
    store: Option<Arc<dyn SdfStore>>,
    by_key: Mutex<BTreeMap<u64, Arc<GridField>>>,
    by_name: Mutex<BTreeMap<String, Arc<GridField>>>,
}

impl std::fmt::Debug for SdfCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SdfCache")
            .field("store", &self.inner.store.is_some())
            .field("entries", &self.inner.by_key.lock().map_or(0, |m| m.len()))
            .finish()
    }
}

impl SdfCache {
    /// A cache in memory only.
    pub fn new() -> Self {
        Self::default()
    }

    /// A cache backed by the host's persistent `store`.
    pub fn with_store(store: Arc<dyn SdfStore>) -> Self {
        Self {
            inner: Arc::new(Inner {
                store: Some(store),
                ..Inner::default()
            }),
        }
    }

    /// Whether two handles share one cache.
    pub fn same(&self, other: &SdfCache) -> bool {
        Arc::ptr_eq(&self.inner, &other.inner)
    }

    /// Number of component SDFs held in memory.
    pub fn len(&self) -> usize {
        self.inner.by_key.lock().map_or(0, |m| m.len())
    }

    /// Whether no SDF is held in memory.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The normalized SDF (§5.2) of closed `mesh`: from memory, from the
    /// store (verified), or computed and then kept (and stored).
    pub fn component_sdf(&self, mesh: &TriMesh) -> Result<Arc<DenseSdf>, SdfError> {
        Ok(self.component_field(mesh)?.sdf.clone())
    }

    /// [`Self::component_sdf`] ready for resampling (with its block
    /// ranges).
    pub fn component_field(&self, mesh: &TriMesh) -> Result<Arc<GridField>, SdfError> {
        self.component_field_at(mesh, None)
    }

    /// The SDF of closed `mesh` as a component: at the library's step
    /// (`None`, [`Self::component_field`]) or with one cell `step` in the
    /// mesh's own units ([`component_sdf_at`], for objects and results
    /// reused at their own resolution).
    pub fn component_field_at(
        &self,
        mesh: &TriMesh,
        step: Option<f64>,
    ) -> Result<Arc<GridField>, SdfError> {
        let key = match step {
            None => mesh_key(mesh),
            Some(s) => mesh_step_key(mesh, s),
        };
        if let Some(s) = self
            .inner
            .by_key
            .lock()
            .ok()
            .and_then(|m| m.get(&key).cloned())
        {
            return Ok(s);
        }
        let sdf = match self.load(key) {
            Some(s) => s,
            None => {
                let s = match step {
                    None => component_sdf(mesh)?,
                    Some(s) => component_sdf_at(mesh, s)?,
                };
                self.store(key, &s);
                s
            }
        };
        let field = Arc::new(GridField::new(
            Arc::new(sdf),
            super::mesh_sdf::normalized_area(mesh),
        ));
        if let Ok(mut m) = self.inner.by_key.lock() {
            m.insert(key, field.clone());
        }
        Ok(field)
    }

    /// The SDF of library component `name`, ready for resampling
    /// (memoized by name, so placing a component does not rebuild and hash
    /// its mesh).
    pub fn library_field(&self, name: &str) -> Result<Arc<GridField>, SdfError> {
        if let Some(s) = self
            .inner
            .by_name
            .lock()
            .ok()
            .and_then(|m| m.get(name).cloned())
        {
            return Ok(s);
        }
        let s = self.component_field(&library::entry(name)?.mesh())?;
        if let Ok(mut m) = self.inner.by_name.lock() {
            m.insert(name.to_owned(), s.clone());
        }
        Ok(s)
    }

    /// The SDF cached under `key` in the store, if present and valid.
    pub fn load(&self, key: u64) -> Option<DenseSdf> {
        let store = self.inner.store.as_ref()?;
        decode(key, &store.load(&key_name(key))?)
    }

    /// Writes `sdf` to the store, if any.
    pub fn store(&self, key: u64, sdf: &DenseSdf) {
        if let Some(s) = &self.inner.store {
            s.store(&key_name(key), &encode(key, sdf));
        }
    }
}

/// The cache key of a mesh's component SDF: the format version and the
/// exact bits of the mesh.
pub fn mesh_key(mesh: &TriMesh) -> u64 {
    let mut h = ContentHasher::new();
    h.u64(FORMAT_VERSION as u64);
    h.mesh(mesh);
    h.finish()
}

/// The cache key of a mesh's component SDF sampled at `step` (see
/// [`SdfCache::component_field_at`]).
pub fn mesh_step_key(mesh: &TriMesh, step: f64) -> u64 {
    let mut h = ContentHasher::new();
    h.u64(FORMAT_VERSION as u64);
    h.bytes(b"step on the lattice");
    h.f64(step);
    h.mesh(mesh);
    h.finish()
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
