//! [`Entry`]: one message of a document's stream (an op, a seed, a
//! snapshot), its format version and the largest one a replica applies.

use serde::{Deserialize, Serialize};

use super::identity::msg_id;
use crate::doc::Op;

/// Version of the entry format, and of what the ops compute: it goes up
/// when a build computes the same ops into different geometry, so that
/// two builds editing one session at once do not go on silently holding
/// different models (issue 33). A replica applies entries of versions
/// [`OLDEST_ENTRY_VERSION`] to this one, but none older than the newest it
/// has taken in: once a newer build has joined or edited, an older build's
/// entries are refused here with a notice to their author. The older
/// build skips the newer one's entries by itself (as of an unknown
/// version, listed in its skipped entries; it has no notice to give,
/// since it never saw the newer author join). What came before the newer
/// build's first entry replays here as this build computes it, as an old
/// file does: a model that differs from what the older build showed, with
/// no word of it.
///
/// - 1: the first shared sessions.
/// - 2 (2026-11-30): a copy of the fused result is the fold of its
///   operands (a build of version 1 ignores `UserMesh::fused` and samples
///   the mesh); disjoint parts are united as one import; a turned part
///   keeps its bearing to its parent's spine.
pub const ENTRY_VERSION: u32 = 2;

/// The oldest entry version this build applies.
pub const OLDEST_ENTRY_VERSION: u32 = 1;

/// The largest entry a replica applies (bytes of JSON): under NATS's
/// default 1 MiB message limit, with room for headers. An op bigger than
/// this (a sculpt stroke of some 10,000 samples; a 90 Hz stroke of ten
/// seconds is about 900) is refused for its author before it is published.
pub const MAX_ENTRY_BYTES: usize = 960 << 10;

/// One message of the stream (the same on the wire as here, JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Format version ([`ENTRY_VERSION`]).
    pub v: u32,
    /// The author's participant id: 1 to 64 bytes of `A-Z a-z 0-9 _ - .`.
    pub author: String,
    /// The author's own entry counter (1, 2, ...): with the author, the
    /// message id the stream de-duplicates on, and the name an undo uses.
    pub n: u64,
    /// The stream sequence the author had seen when publishing it.
    pub base: u64,
    /// What it does.
    pub body: Body,
}

/// What an entry does.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Body {
    /// The author joins (or rejoins, with a new name or colour).
    Join {
        /// The name shown to others.
        name: String,
        /// Their colour (linear RGB, 0 to 1).
        colour: [f32; 3],
    },
    /// An op.
    Op {
        /// The first id the op's created objects take (absent: it
        /// creates none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        ids_from: Option<u32>,
        /// The op, as in a `.jsonl` script.
        op: Op,
    },
    /// Takes back the author's op `n`.
    Undo(u64),
    /// Brings back the author's undone op `n`.
    Redo(u64),
    /// The single-user history the session starts from (a file someone
    /// opened and then shared): valid only as the first op entry. Its
    /// objects keep their ids (below the participants' ranges); nobody's
    /// undo takes it back.
    Seed(Vec<Op>),
}

impl Entry {
    /// A version-[`ENTRY_VERSION`] entry: `author`'s `n`th, published
    /// having seen the stream up to `base`.
    pub fn new(author: &str, n: u64, base: u64, body: Body) -> Self {
        Entry {
            v: ENTRY_VERSION,
            author: author.into(),
            n,
            base,
            body,
        }
    }

    /// The message id the stream de-duplicates on (`Nats-Msg-Id`).
    pub fn msg_id(&self) -> String {
        msg_id(&self.author, self.n)
    }

    /// The entry as a stream message.
    pub fn to_bytes(&self) -> Vec<u8> {
        serde_json::to_vec(self).unwrap_or_default()
    }
}
