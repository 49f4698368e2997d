//! What [`super::union_mesh_cached`] keeps between evaluations of one
//! assembly (issue 21, "Unions": an edit re-unites only what changed).
//!
//! Every entry is keyed by content, never by position in history: a part's
//! mesh and cavity by the [`ContentHasher`] hash of its GC's exact JSON
//! (serde prints every f64 exactly), a part's trimmed mesh by its index,
//! its GC's hash and the hashes of the cavities cut out of it, a node of
//! the union tree by its groups and their trimmed parts' keys, the final mesh
//! by the root's key. So an entry is reused exactly when recomputing it
//! would give the same bits, whichever op, undo or redo led there, and the
//! result never depends on what the cache holds (a fresh cache gives the
//! same mesh: the assembly tests compare both). A 64-bit key can collide;
//! with the hash's avalanche the odds are about 2^-64 per pair of
//! distinct values, which we accept as the document hash does.
//!
//! Choices: the cache is shared (`Arc`) by every version of a document
//! object, from the op that created it through its edits, checkpoints,
//! undo and redo ([`crate::doc::Object::cache`]); it is not content (not
//! saved, not hashed). Entries are dropped least recently used first once
//! their estimated size passes [`UnionCache::DEFAULT_BUDGET`]; the entries
//! of the evaluation running now and of the one before it are never
//! dropped, so an edit finds what the last evaluation made whatever its
//! size (a 1 M-triangle union node alone is twice the budget: it was
//! dropped as soon as the next evaluation meshed its changed part, and
//! the edit re-united every part; [`crate::gc::budget`] estimates an
//! edit's time on the last evaluation being kept). A result found whole
//! marks its tree's nodes and its parts' trims used too (an undo, then an
//! edit). The lock is held
//! only to look up and insert, never while meshing or uniting.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};

use crate::hash::ContentHasher;
use crate::mesh::{TriMesh, UnionOperand};

/// Counters of cache use, for tests and diagnostics (not content).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheStats {
    /// Part meshes taken from the cache.
    pub mesh_hits: u64,
    /// Part meshes computed ([`crate::gc::mesh_gc`]).
    pub mesh_misses: u64,
    /// Part cavities taken from the cache.
    pub cavity_hits: u64,
    /// Part cavities computed ([`crate::gc::cavity_gc`]).
    pub cavity_misses: u64,
    /// Trimmed part meshes taken from the cache.
    pub trim_hits: u64,
    /// Trimmed part meshes computed (a boolean difference, or the part's
    /// mesh as is when nothing cuts it).
    pub trim_misses: u64,
    /// Parts whose union was taken from the cache: the parts under the
    /// union tree's nodes found whole (a part alone in its group counts
    /// with its imported mesh, the node over it alone).
    pub parts_reused: u64,
    /// Union steps computed (one boolean each).
    pub union_steps: u64,
    /// Whole results taken from the cache.
    pub result_hits: u64,
}

/// A cached value.
#[derive(Clone, Debug)]
pub(super) enum Value {
    /// A part's mesh as [`crate::gc::mesh_gc`] gives it.
    Mesh(Arc<TriMesh>),
    /// A part's cavity as [`crate::gc::cavity_gc`] gives it.
    Cavity(Arc<Option<TriMesh>>),
    /// A part's mesh with its sources set and the other parts' cavities
    /// cut out.
    Trimmed(Arc<TriMesh>),
    /// A node of the union tree: the union of a range of the trimmed
    /// parts (`None`: all empty).
    Node(Option<Arc<UnionOperand>>),
    /// The checked union of all parts.
    Result(Arc<TriMesh>),
}

impl Value {
    fn bytes(&self) -> usize {
        fn mesh(m: &TriMesh) -> usize {
            m.positions.len() * 24
                + m.normals.len() * 24
                + m.triangles.len() * 12
                + m.tri_source.len() * 4
        }
        64 + match self {
            Self::Mesh(m) | Self::Trimmed(m) | Self::Result(m) => mesh(m),
            Self::Cavity(c) => c.as_ref().as_ref().map_or(0, mesh),
            // Halfedges, face and vertex data, triangle references and the
            // collider: about 200 bytes a triangle in manifold-rust.
            Self::Node(p) => p.as_ref().map_or(0, |u| 200 * u.triangle_count()),
        }
    }
}

/// Which kind of value a key names (keys of different kinds never meet).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Tag {
    Mesh,
    Cavity,
    Trimmed,
    Node,
    Result,
}

#[derive(Debug)]
struct Entry {
    value: Value,
    bytes: usize,
    /// The evaluation that last used it.
    used: u64,
    /// Insertion order, to break ties (older goes first).
    seq: u64,
}

#[derive(Debug, Default)]
struct State {
    entries: HashMap<(Tag, u64), Entry>,
    bytes: usize,
    evaluation: u64,
    seq: u64,
    stats: CacheStats,
}

/// The evaluation cache of one assembly object: part meshes, cavities,
/// trimmed parts, nodes of the union tree and results, each keyed by
/// content so that reusing one never changes a result (see
/// [`super::union_mesh_cached`]). Cloning shares it.
#[derive(Clone)]
pub struct UnionCache {
    state: Arc<Mutex<State>>,
    budget: usize,
}

impl std::fmt::Debug for UnionCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = self.lock();
        write!(
            f,
            "UnionCache({} entries, {} bytes)",
            s.entries.len(),
            s.bytes
        )
    }
}

impl Default for UnionCache {
    fn default() -> Self {
        Self::with_budget(Self::DEFAULT_BUDGET)
    }
}

impl UnionCache {
    /// Estimated bytes kept before the least recently used entries go:
    /// about three chair-sized (110k-triangle) union nodes, or a hundred
    /// part meshes.
    pub const DEFAULT_BUDGET: usize = 96 << 20;

    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty cache keeping about `budget` bytes.
    pub fn with_budget(budget: usize) -> Self {
        Self {
            state: Arc::new(Mutex::new(State::default())),
            budget,
        }
    }

    /// Counters since the cache was made.
    pub fn stats(&self) -> CacheStats {
        self.lock().stats
    }

    /// Estimated bytes held.
    pub fn bytes(&self) -> usize {
        self.lock().bytes
    }

    /// Entries held.
    pub fn len(&self) -> usize {
        self.lock().entries.len()
    }

    /// True when nothing is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic while holding the lock cannot leave an entry half made
        // (inserts are single map operations): keep using the state.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Starts an evaluation: what it uses is protected from eviction
    /// until the one after the next starts.
    pub(super) fn begin(&self) {
        self.lock().evaluation += 1;
    }

    /// The value under `(tag, key)`, marked used.
    pub(super) fn get(&self, tag: Tag, key: u64) -> Option<Value> {
        let mut s = self.lock();
        let now = s.evaluation;
        let e = s.entries.get_mut(&(tag, key))?;
        e.used = now;
        Some(e.value.clone())
    }

    /// Stores `value` under `(tag, key)` and drops least recently used
    /// entries of the evaluations before the last one while over budget.
    pub(super) fn put(&self, tag: Tag, key: u64, value: Value) {
        let mut s = self.lock();
        let (now, seq) = (s.evaluation, s.seq);
        s.seq += 1;
        let bytes = value.bytes();
        let entry = Entry {
            value,
            bytes,
            used: now,
            seq,
        };
        if let Some(old) = s.entries.insert((tag, key), entry) {
            s.bytes -= old.bytes;
        }
        s.bytes += bytes;
        while s.bytes > self.budget {
            let Some((&k, e)) = s
                .entries
                .iter()
                .filter(|(_, e)| e.used + 1 < now)
                .min_by_key(|(_, e)| (e.used, e.seq))
            else {
                break;
            };
            let b = e.bytes;
            s.entries.remove(&k);
            s.bytes -= b;
        }
    }

    /// Counts in the stats.
    pub(super) fn count(&self, f: impl FnOnce(&mut CacheStats)) {
        f(&mut self.lock().stats);
    }
}

/// A key mixing a tag word and `words`.
pub(super) fn key(tag: &[u8], words: &[u64]) -> u64 {
    let mut h = ContentHasher::new();
    h.bytes(tag);
    for w in words {
        h.u64(*w);
    }
    h.finish()
}

/// The content key of a GC: its exact JSON.
pub(super) fn gc_key(gc: &crate::gc::Gc) -> u64 {
    let mut h = ContentHasher::new();
    h.bytes(b"gc");
    h.bytes(serde_json::to_string(gc).unwrap_or_default().as_bytes());
    h.finish()
}
