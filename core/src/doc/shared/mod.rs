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
//! (checkpoints as in [`super::LinearLog`]), never from the empty document.
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
//! ordinary [`super::LinearLog`] (the ops in effect, each creation preceded by
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

mod entry;
mod identity;
mod ids;

pub use entry::{Body, Entry, ENTRY_VERSION, MAX_ENTRY_BYTES, OLDEST_ENTRY_VERSION};
pub use identity::{colour_for, id_from_token, msg_id, subject_token, valid_author};
use ids::apply_op;
pub use ids::{id_range, ID_RANGE_BITS, MAX_PARTICIPANTS};
