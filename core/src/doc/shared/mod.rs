//! Shared sessions: several people model one document, each with their
//! own undo (issue 23). This module is the whole of the semantics, with
//! no network in it: the transport (`shapewright-net`, NATS JetStream)
//! only carries [`Entry`] bytes in one total order and hands them back.
//!
//! **The log is a stream of entries.** Every participant's [`Replica`]
//! applies the same entries in the same (stream) order with the same
//! rules, so every replica has the same document, bit for bit, after the
//! same sequence. An entry is one of: a participant joining
//! ([`Body::Join`], which gives them an id range), an op ([`Body::Op`]),
//! or an undo or redo naming one of the author's own ops.
//!
//! **The document is the replay of the stream with undone ops skipped.**
//! An undo does not step a cursor back: it marks the named op undone, and
//! the document becomes the replay of every op not undone, in stream
//! order. An op that fails in that replay (it moved an object whose
//! creation was undone) is skipped, the same way on every replica, and its
//! author is told ([`Notice`]); a redo of the undone op brings both back.
//! So one person's undo never takes back another person's work. Undo near
//! the head replays only from the nearest checkpoint before the undone op
//! (checkpoints as in [`super::OpLog`]), never from the empty document.
//!
//! **Ids that do not collide.** The n-th participant to join gets id range
//! n (ids `n << 24 + 1 ..`, n from 1 to [`MAX_PARTICIPANTS`]); a
//! single-user document's objects keep their ids below `1 << 24`. An op
//! that creates objects carries the first id it takes (`ids_from`, from
//! its author's own counter) and the replica makes the document take ids
//! from there (`reserve_ids`). Ids therefore depend only on the op, not on
//! what others did meanwhile: an op rebased onto someone else's keeps its
//! ids, and so do the author's later ops that name them. A creation that
//! would take an id in use is refused ([`super::OpError::IdInUse`]).
//!
//! **Optimistic, then confirmed.** [`SharedLog`] is what a host holds: the
//! confirmed replica (entries the stream has) plus the participant's own
//! pending entries applied on top, so an edit shows at once. Entries are
//! appended conditionally on the last sequence the client has seen; when
//! someone else's entry lands first, the pending entries are re-applied on
//! the new head (rebase) and those that no longer apply are refused for
//! their author with the op's own error, never published.
//!
//! **Saving.** [`SharedLog::linear_log`] flattens the document into an
//! ordinary [`super::OpLog`] (the ops in effect, each creation preceded by
//! its `reserve_ids`), which replays to the same bits: a shared model saves
//! as USD and opens in Blender with its history, like any other.
//!
//! Choices made here (the issue is silent on them):
//! - An undo takes back the author's latest op that is in effect; an op
//!   that is skipped (someone removed what it needed) is passed over, as
//!   it shows nothing to take back.
//! - A new op clears its author's redo list, as in single-user history;
//!   others' ops do not.
//! - An entry is refused (skipped with a logged reason, identically
//!   everywhere) when it is not valid JSON, larger than [`MAX_ENTRY_BYTES`],
//!   sent on another person's subject than its author's, from someone who
//!   has not joined, a duplicate of one already applied, reserves ids
//!   outside its author's range, or undoes what is not its author's to
//!   undo.
//!
//! **Authorship is the sender's.** Each person appends on a subject of
//! their own (`sw.DOC.log.<token>`, [`subject_token`]), which the server
//! lets only that person publish on (issue 35); the transport hands each
//! message to [`Replica::integrate`] with the token of the subject it came
//! on, and an entry whose `author` is not that subject's person is refused
//! by every replica, with a notice to both the sender and the person it
//! claimed to be. So nobody can join, edit, undo or redo as someone else.
//!
//! **Snapshots are checked, not trusted** ([`SnapshotCheck`]): a joiner
//! that starts from a snapshot replays the stream up to the snapshot's
//! sequence in the background and, when the two differ, switches to the
//! stream's document ([`SharedLog::adopt`]), telling the person whose
//! snapshot it was.

mod client;
mod presence;
mod replica;
#[cfg(test)]
mod tests;
mod verify;

pub use client::{Publish, Published, SharedError, SharedLog, DEFAULT_SNAPSHOT_EVERY};
pub use presence::{
    Presence, PresenceError, PresencePose, MAX_PRESENCE_BYTES, PRESENCE_HZ, PRESENCE_STALE_SECS,
    PRESENCE_VERSION,
};
pub use replica::{
    EntryError, Integrated, Notice, NoticeKind, Participant, Replica, Skipped, SNAPSHOT_FORMAT,
};
pub use verify::{SnapshotCheck, Verdict};

use serde::{Deserialize, Serialize};

use super::Op;

/// Version of the entry format.
pub const ENTRY_VERSION: u32 = 1;

/// The largest entry a replica applies (bytes of JSON): under NATS's
/// default 1 MiB message limit, with room for headers. An op bigger than
/// this (a sculpt stroke of some 10,000 samples; a 90 Hz stroke of ten
/// seconds is about 900) is refused for its author before it is published.
pub const MAX_ENTRY_BYTES: usize = 960 << 10;

/// How many people can join one document (each gets an id range).
pub const MAX_PARTICIPANTS: u32 = 127;

/// Ids of participant `slot` are `slot << ID_RANGE_BITS` and up.
pub const ID_RANGE_BITS: u32 = 24;

/// The first and one past the last id of participant `slot`'s range.
pub fn id_range(slot: u32) -> (u32, u32) {
    let first = (slot << ID_RANGE_BITS) + 1;
    (first, (slot + 1) << ID_RANGE_BITS)
}

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
    /// The message id the stream de-duplicates on (`Nats-Msg-Id`).
    pub fn msg_id(&self) -> String {
        msg_id(&self.author, self.n)
    }

    /// The entry as a stream message.
    pub fn to_bytes(&self) -> Vec<u8> {
        serde_json::to_vec(self).unwrap_or_default()
    }
}

/// A participant's colour, from their id (hosts draw them with it):
/// saturated and light enough to read on the headset's dark background.
pub fn colour_for(id: &str) -> [f32; 3] {
    let h = id.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    });
    let hue = (h % 360) as f32 / 60.0;
    let x = 1.0 - (hue % 2.0 - 1.0).abs();
    let (r, g, b) = match hue as u32 {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        3 => (0.0, x, 1.0),
        4 => (x, 0.0, 1.0),
        _ => (1.0, 0.0, x),
    };
    [0.25 + 0.75 * r, 0.25 + 0.75 * g, 0.25 + 0.75 * b]
}

/// The message id of `author`'s entry `n`.
pub fn msg_id(author: &str, n: u64) -> String {
    format!("{author}:{n}")
}

/// True when `id` is a valid participant id.
pub fn valid_author(id: &str) -> bool {
    !id.is_empty()
        && id.len() <= 64
        && id
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || b == b'.')
}

/// Participant `id` as one token of a NATS subject (the last of
/// `sw.DOC.log.<token>` and `sw.DOC.presence.<token>`): a `.` would split
/// the subject, so it becomes `%2E`; ids never hold `%`, so two ids never
/// share a token. `None` when `id` is not a valid participant id.
pub fn subject_token(id: &str) -> Option<String> {
    valid_author(id).then(|| id.replace('.', "%2E"))
}

/// The participant id whose [`subject_token`] is `token`, if any.
pub fn id_from_token(token: &str) -> Option<String> {
    let id = token.replace("%2E", ".");
    (subject_token(&id).as_deref() == Some(token)).then_some(id)
}

/// Applies `op` to `doc` taking ids from `ids_from` (if any); every id it
/// takes must lie in `range` (its author's). A reservation that created
/// nothing is taken back, so the document is as if it was never made.
/// Shared by the replica and the client so both decide identically.
fn apply_op(
    doc: &mut super::Document,
    op: &Op,
    ids_from: Option<u32>,
    range: (u32, u32),
) -> Result<super::OpOutcome, super::OpError> {
    use super::{ObjectId, OpError};
    super::schema::check_op(op)?;
    let saved = doc.id_block();
    let last = doc.last_id();
    if let Some(first) = ids_from {
        if first < range.0 || first >= range.1 {
            return Err(OpError::IdOutsideRange(ObjectId(first)));
        }
        doc.reserve_ids(first)?;
    }
    let outcome = op.apply(doc)?;
    match ids_from {
        Some(first) => {
            let end = doc.id_block().unwrap_or(first);
            if end == first {
                doc.set_id_block(saved);
            } else if end > range.1 {
                return Err(OpError::IdOutsideRange(ObjectId(end - 1)));
            }
        }
        None if doc.last_id() != last || doc.id_block() != saved => {
            return Err(OpError::IdOutsideRange(doc.next_id()));
        }
        None => {}
    }
    Ok(outcome)
}
