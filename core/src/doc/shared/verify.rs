//! [`SnapshotCheck`]: a snapshot a late joiner started from, checked
//! against the stream's own replay (issue 35, "snapshots cannot
//! mislead").
//!
//! A snapshot is a claim by whoever stored it: "the stream up to sequence
//! S is this replica". The stream itself is the truth (the server orders
//! it, and each entry is bound to its sender, see [`super::subject_token`]).
//! Three designs were weighed:
//! - **A trusted snapshot writer** (a keeper process with the only
//!   credentials for the bucket). It moves the trust to a process every
//!   team must run and keep beside the server, and a session without it
//!   has no snapshots; an open server (no member list) still trusts
//!   whatever is in the bucket.
//! - **A hash chain carried by the entries.** The entries' hashes can only
//!   be vouched for by their authors, and one dishonest editor can vouch
//!   for a forged state as well as an honest one can for the true one: a
//!   joiner cannot tell which claim to believe without replaying.
//! - **Replay and compare (chosen).** The joiner starts from the snapshot
//!   at once (a late join stays fast), replays the stream up to the
//!   snapshot's sequence in the background, and compares the replay's
//!   snapshot with the one it loaded, byte for byte (a replica's snapshot
//!   is a deterministic function of the stream, so an honest one is
//!   identical). When they differ it switches to the replay, brought up
//!   to date with the entries that arrived meanwhile
//!   ([`super::SharedLog::adopt`]): its own edits made meanwhile are
//!   re-applied on the true document (those already in the stream were
//!   always judged by the stream's rules, so nothing of anyone's is lost),
//!   and the person is told whose snapshot misled them. This needs no
//!   trusted party and no server configuration, also holds on an open
//!   server, and costs one background replay per join (3.9 s of one
//!   core for a 10,000-entry stream here, see the README's bench rows).
//!
//! What it does not do: the document shown during the replay is the
//! snapshot's; a forged one shows for those seconds (and the person's
//! edits in that window act on what they saw, then are re-applied on the
//! truth, or refused with the reason).

use super::{Replica, SharedLog};

/// The background half of a joiner's snapshot check: the stream replayed
/// from its start up to the snapshot's sequence. `Send`, so a transport
/// may run it on a thread of its own.
pub struct SnapshotCheck {
    seq: u64,
    claimed: Vec<u8>,
    replay: Replica,
}

/// What a [`SnapshotCheck`] found.
pub enum Verdict {
    /// The snapshot is the stream's replay: nothing to do.
    Same,
    /// It is not: the stream's replay up to the snapshot's sequence, to be
    /// brought up to date and adopted ([`Verdict::settle`]).
    Differs(Box<Replica>),
}

impl SnapshotCheck {
    /// Checks the snapshot `claimed` (its bytes, as loaded) that says it
    /// holds the stream up to sequence `seq`.
    pub fn new(seq: u64, claimed: Vec<u8>) -> Self {
        Self {
            seq,
            claimed,
            replay: Replica::new(),
        }
    }

    /// The sequence the snapshot claims to cover.
    pub fn seq(&self) -> u64 {
        self.seq
    }

    /// Feeds the stream's message at `seq` (from the stream's start, in
    /// order; `from` is its subject's last token). Returns the verdict once
    /// the replay has reached the snapshot's sequence; a message past it is
    /// not applied (it only says the stream went on without the snapshot's
    /// sequence, which then cannot be the stream's).
    pub fn feed(&mut self, seq: u64, from: &str, bytes: &[u8]) -> Option<Verdict> {
        if seq <= self.seq {
            self.replay.integrate(seq, from, bytes);
        }
        (self.replay.last_seq() >= self.seq || seq > self.seq).then(|| self.verdict())
    }

    /// The verdict on what was fed so far (a stream that ended before the
    /// snapshot's sequence makes the snapshot differ).
    pub fn verdict(&mut self) -> Verdict {
        if self.replay.last_seq() == self.seq && self.replay.snapshot() == self.claimed {
            Verdict::Same
        } else {
            let replay = std::mem::take(&mut self.replay);
            Verdict::Differs(Box::new(replay))
        }
    }
}

impl Verdict {
    /// Applies the verdict to `log`, the joiner's session started from the
    /// snapshot: on [`Verdict::Differs`], the replay takes the entries
    /// `live` that `log` applied after the snapshot (in order, with their
    /// subjects' tokens) and `log` adopts it, telling its person `why`.
    /// Returns whether `log` changed.
    pub fn settle(self, log: &mut SharedLog, live: &[(u64, String, Vec<u8>)], why: &str) -> bool {
        let Verdict::Differs(mut truth) = self else {
            return false;
        };
        for (seq, from, bytes) in live {
            truth.integrate(*seq, from, bytes);
        }
        // A stream without the snapshot's sequence (and nothing since):
        // there is nothing between the replay's end and the live one's.
        truth.skip_to(log.confirmed().last_seq());
        let _ = truth.take_notices();
        log.adopt(*truth, why)
    }
}
