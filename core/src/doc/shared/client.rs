//! [`SharedLog`]: one participant's side of a shared session: the
//! confirmed [`Replica`] plus their own pending entries applied on top,
//! what to publish next, and the rebase when someone else's entry lands
//! first. See the module doc of [`super`].

use std::collections::VecDeque;

use super::replica::EntryError;
use super::{valid_author, Body, Entry, Notice, NoticeKind, Replica};
use super::{MAX_ENTRY_BYTES, MAX_PARTICIPANTS};
use crate::doc::{Document, LinearLog, LogError, Op, OpError, OpOutcome};

/// Entries between snapshots unless set otherwise.
pub const DEFAULT_SNAPSHOT_EVERY: u64 = 1000;

/// Why a shared-session action was refused. The document is unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SharedError {
    /// Creating needs the participant's id range, which the server gives
    /// when it has their join (an offline participant who never joined
    /// has none yet).
    #[error("not joined yet: the session's server has not confirmed that you joined, so you have no id range to create objects in")]
    NotJoined,
    /// The participant id is not 1 to 64 bytes of `A-Z a-z 0-9 _ - .`,
    /// or the name is over 64 bytes or has control characters, or the
    /// colour is not linear RGB in 0 to 1.
    #[error("bad participant: {0}")]
    BadParticipant(String),
    /// None of this participant's ops is in effect.
    #[error("nothing of yours to undo")]
    NothingToUndo,
    /// This participant undid nothing since their last op.
    #[error("nothing of yours to redo")]
    NothingToRedo,
    /// The op failed on the document.
    #[error(transparent)]
    Op(#[from] OpError),
    /// The entry was refused (too large, ...).
    #[error("{0}")]
    Refused(String),
    /// The session's server refused this participant's appends: they may
    /// only view the document (see [`SharedLog::deny`]).
    #[error("view only: {0}")]
    ViewOnly(String),
}

impl From<EntryError> for SharedError {
    fn from(e: EntryError) -> Self {
        match e {
            EntryError::Op(e) => Self::Op(e),
            EntryError::Refused(why) => Self::Refused(why),
        }
    }
}

impl From<SharedError> for LogError {
    fn from(e: SharedError) -> Self {
        match e {
            SharedError::NothingToUndo => LogError::NothingToUndo,
            SharedError::NothingToRedo => LogError::NothingToRedo,
            SharedError::Op(e) => LogError::Op(e),
            other => LogError::Shared(other.to_string()),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sent {
    No,
    InFlight,
    /// Stored by the server at this sequence, not yet back through the
    /// subscription.
    Acked(u64),
}

#[derive(Clone, Debug)]
struct Pending {
    entry: Entry,
    sent: Sent,
}

/// One message to append to the stream: its bytes, message id and the
/// sequence the append is conditional on (the stream's last must be this
/// one, else someone else's entry landed first).
#[derive(Clone, Debug, PartialEq)]
pub struct Publish {
    /// The entry's counter (to report the result with).
    pub n: u64,
    /// The message id (`Nats-Msg-Id`).
    pub msg_id: String,
    /// The stream's last sequence this append expects.
    pub expected_last_seq: u64,
    /// The message.
    pub bytes: Vec<u8>,
}

/// How an append ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Published {
    /// Stored at this stream sequence.
    Stored(u64),
    /// Someone else's entry landed first: wait for it, rebase, retry.
    Conflict,
    /// The server could not be reached (offline): retry on reconnect.
    Failed,
}

/// One participant's shared session: what their host applies edits to
/// instead of a [`LinearLog`] (through [`crate::doc::OpLog`], which routes to
/// either).
#[derive(Clone, Debug)]
pub struct SharedLog {
    me: String,
    confirmed: Replica,
    /// `confirmed` with the pending entries applied (None: none pending).
    view: Option<Replica>,
    pending: VecDeque<Pending>,
    next_n: u64,
    /// The next id of our range a creation takes (None: not joined yet).
    next_id: Option<u32>,
    /// An append conflicted when the stream's last was at most this: wait
    /// for a newer entry before appending again.
    blocked_at: Option<u64>,
    notices: Vec<Notice>,
    /// Entries between snapshots (see [`Self::snapshot_due`]).
    snapshot_every: u64,
    /// The last snapshot boundary passed (`seq / snapshot_every`).
    snapshot_k: u64,
    /// Our entry crossed a boundary: we write that snapshot.
    snapshot_due: bool,
    /// The server refused our appends, saying this (a viewer).
    view_only: Option<String>,
}

impl SharedLog {
    /// A participant `me` (shown as `name` in `colour`) about to join a
    /// session; their join is the first entry to publish.
    pub fn new(me: &str, name: &str, colour: [f32; 3]) -> Result<Self, SharedError> {
        Self::resume(me, name, colour, Replica::new(), 1)
    }

    /// A participant rejoining a session whose entries up to some sequence
    /// are in `confirmed` (replayed, or restored from a snapshot), their
    /// next entry counter being at least `next_n`. They join again (a
    /// rejoin keeps their id range).
    pub fn resume(
        me: &str,
        name: &str,
        colour: [f32; 3],
        confirmed: Replica,
        next_n: u64,
    ) -> Result<Self, SharedError> {
        if !valid_author(me) {
            return Err(SharedError::BadParticipant(format!(
                "participant id `{}` must be 1 to 64 bytes of A-Z a-z 0-9 _ - .",
                me.chars().take(80).collect::<String>()
            )));
        }
        if name.len() > 64 || name.chars().any(char::is_control) {
            return Err(SharedError::BadParticipant(
                "a name must be at most 64 bytes without control characters".into(),
            ));
        }
        if colour
            .iter()
            .any(|c| !c.is_finite() || !(0.0..=1.0).contains(c))
        {
            return Err(SharedError::BadParticipant(format!(
                "colour {colour:?} is not linear RGB between 0 and 1"
            )));
        }
        let seen = confirmed.participant(me).map_or(0, |p| p.last_n);
        if confirmed.participant(me).is_none()
            && confirmed.participants().len() as u32 >= MAX_PARTICIPANTS
        {
            return Err(SharedError::Refused(format!(
                "the session is full ({MAX_PARTICIPANTS} participants)"
            )));
        }
        let mut log = Self {
            me: me.to_string(),
            next_id: confirmed.next_free_id(me),
            confirmed,
            view: None,
            pending: VecDeque::new(),
            next_n: next_n.max(seen + 1),
            blocked_at: None,
            notices: Vec::new(),
            snapshot_every: DEFAULT_SNAPSHOT_EVERY,
            snapshot_k: 0,
            snapshot_due: false,
            view_only: None,
        };
        log.snapshot_k = log.confirmed.last_seq() / log.snapshot_every;
        log.push_local(Body::Join {
            name: name.to_string(),
            colour,
        })?;
        Ok(log)
    }

    /// The counter this participant's next entry will have.
    pub fn next_n(&self) -> u64 {
        self.next_n
    }

    /// This participant's id.
    pub fn me(&self) -> &str {
        &self.me
    }

    /// The document as this participant sees it: the confirmed one with
    /// their pending entries applied.
    pub fn document(&self) -> &Document {
        self.view().document()
    }

    /// The entries the stream has confirmed.
    pub fn confirmed(&self) -> &Replica {
        &self.confirmed
    }

    /// The confirmed replica with the pending entries applied.
    pub fn view(&self) -> &Replica {
        self.view.as_ref().unwrap_or(&self.confirmed)
    }

    /// True once the server has this participant's join.
    pub fn is_joined(&self) -> bool {
        self.next_id.is_some()
    }

    /// Entries not yet back from the stream.
    pub fn pending_count(&self) -> usize {
        self.pending.len()
    }

    /// Takes the notices about this participant's entries (refused on
    /// arrival or on a rebase, skipped or restored by others' undos).
    pub fn take_notices(&mut self) -> Vec<Notice> {
        std::mem::take(&mut self.notices)
    }

    /// True when this participant has an op in effect to undo.
    pub fn can_undo(&self) -> bool {
        self.view().undo_target(&self.me).is_some()
    }

    /// True when this participant undid something since their last op.
    pub fn can_redo(&self) -> bool {
        self.view().redo_target(&self.me).is_some()
    }

    /// Applies `op` at once (pending until the stream confirms it). A
    /// creation takes ids from this participant's own range.
    pub fn apply(&mut self, op: Op) -> Result<OpOutcome, SharedError> {
        self.writable()?;
        let Some(first) = self.next_id else {
            return Err(SharedError::NotJoined);
        };
        let outcome = self.push_local(Body::Op {
            ids_from: Some(first),
            op,
        })?;
        Ok(outcome.unwrap_or_default())
    }

    /// Starts the session from a single-user history (a file this
    /// participant opened): only as the session's first op entry.
    pub fn seed(&mut self, ops: Vec<Op>) -> Result<(), SharedError> {
        self.writable()?;
        if !self.is_joined() {
            return Err(SharedError::NotJoined);
        }
        self.push_local(Body::Seed(ops)).map(|_| ())
    }

    /// Takes back this participant's latest op in effect.
    pub fn undo(&mut self) -> Result<(), SharedError> {
        self.writable()?;
        let target = self
            .view()
            .undo_target(&self.me)
            .ok_or(SharedError::NothingToUndo)?;
        self.push_local(Body::Undo(target)).map(|_| ())
    }

    /// Brings back this participant's last undone op.
    pub fn redo(&mut self) -> Result<(), SharedError> {
        self.writable()?;
        let target = self
            .view()
            .redo_target(&self.me)
            .ok_or(SharedError::NothingToRedo)?;
        self.push_local(Body::Redo(target)).map(|_| ())
    }

    /// The server refused this participant's appends (`why` says how): they
    /// may only view the document. Every pending entry is dropped (the view
    /// is the stream's document again), each dropped op is reported once
    /// as refused, and every later edit fails with
    /// [`SharedError::ViewOnly`]. Entries keep arriving as before.
    pub fn deny(&mut self, why: &str) {
        if self.view_only.is_some() {
            return;
        }
        for p in std::mem::take(&mut self.pending) {
            if matches!(p.entry.body, Body::Join { .. }) {
                continue;
            }
            self.notices.push(Notice {
                author: self.me.clone(),
                n: p.entry.n,
                kind: NoticeKind::Refused,
                message: format!("not sent: you may only view this document ({why})"),
            });
        }
        self.view = None;
        self.blocked_at = None;
        self.view_only = Some(why.to_string());
    }

    fn writable(&self) -> Result<(), SharedError> {
        match &self.view_only {
            Some(why) => Err(SharedError::ViewOnly(why.clone())),
            None => Ok(()),
        }
    }

    /// Why this participant may only view the document, once the server
    /// refused an append (see [`Self::deny`]).
    pub fn view_only(&self) -> Option<&str> {
        self.view_only.as_deref()
    }

    /// Makes `body` this participant's next entry and applies it to the
    /// view; on error nothing changes.
    fn push_local(&mut self, body: Body) -> Result<Option<OpOutcome>, SharedError> {
        self.writable()?;
        let mut entry = Entry::new(&self.me, self.next_n, 0, body);
        let size = serde_json::to_vec(&entry).map_or(usize::MAX, |b| b.len());
        if size > MAX_ENTRY_BYTES {
            return Err(SharedError::Refused(format!(
                "this edit is {size} bytes, more than the {MAX_ENTRY_BYTES} a shared session carries in one entry"
            )));
        }
        // On a copy: a refused entry leaves the view as it was.
        let mut view = self.view().clone();
        let block = view.document().id_block();
        let outcome = view.apply_entry(&entry)?;
        let _ = view.take_notices();
        if let Body::Op { ids_from, .. } = &mut entry.body {
            let after = view.document().id_block();
            if after == block || after.is_none() {
                *ids_from = None;
            } else {
                self.next_id = after;
            }
        }
        self.next_n += 1;
        self.pending.push_back(Pending {
            entry,
            sent: Sent::No,
        });
        self.view = Some(view);
        Ok(outcome)
    }

    /// Applies the stream's message at `seq` (in stream order), sent on
    /// the subject whose last token is `from` (see
    /// [`Replica::integrate`]): our own entry coming back confirms it;
    /// anyone else's rebases our pending entries onto it.
    /// Returns the entry's author and counter when it decoded.
    pub fn integrate(&mut self, seq: u64, from: &str, bytes: &[u8]) -> Option<(String, u64)> {
        let r = self.confirmed.integrate(seq, from, bytes);
        if r.redelivery {
            return None;
        }
        let key = r.key.clone();
        let me = self.me.clone();
        self.notices.extend(
            self.confirmed
                .take_notices()
                .into_iter()
                .filter(|n| n.author == me),
        );
        if self.next_id.is_none() {
            self.next_id = self.confirmed.next_free_id(&self.me);
        }
        let ours = matches!(
            (&r.key, self.pending.front()),
            (Some((a, n)), Some(p)) if *a == self.me && *n == p.entry.n
        );
        // An entry under our id that we did not make (a second host with
        // the same participant id, or a spoof): our counters move past it.
        let ours_by_id = matches!(&r.key, Some((a, _)) if *a == self.me);
        if let (true, Some(p)) = (ours_by_id && !ours, self.confirmed.participant(&self.me)) {
            self.next_n = self.next_n.max(p.last_n + 1);
            if let (Some(mine), Some(free)) = (self.next_id, self.confirmed.next_free_id(&self.me))
            {
                self.next_id = Some(mine.max(free));
            }
        }
        if r.result.is_ok() && seq / self.snapshot_every > self.snapshot_k {
            // The first good entry past a boundary: its author writes the
            // snapshot (everyone agrees who that is).
            self.snapshot_k = seq / self.snapshot_every;
            self.snapshot_due = ours;
        }
        if ours && r.result.is_ok() {
            self.pending.pop_front();
            if self.pending.is_empty() {
                self.view = None;
            }
            return key;
        }
        if ours {
            self.pending.pop_front();
        }
        self.rebase();
        key
    }

    /// Replaces the confirmed replica with `truth`, the stream's own
    /// replay up to the same sequence (a joiner's snapshot turned out to
    /// differ from it, see [`super::SnapshotCheck`]): the pending entries
    /// are re-applied on it, counters and the id range move past anything
    /// of ours it holds, and this participant is told `why`. Refused
    /// (returns false, nothing changes) when `truth` is not at the
    /// confirmed replica's sequence.
    pub fn adopt(&mut self, truth: Replica, why: &str) -> bool {
        if truth.last_seq() != self.confirmed.last_seq() {
            return false;
        }
        self.confirmed = truth;
        if let Some(p) = self.confirmed.participant(&self.me) {
            self.next_n = self.next_n.max(p.last_n + 1);
        }
        self.notices.push(Notice {
            author: self.me.clone(),
            n: 0,
            kind: NoticeKind::Replaced,
            message: why.to_string(),
        });
        // Pending creations made in a range the snapshot gave us but the
        // stream does not are refused here; the next id is the stream's.
        self.rebase();
        self.next_id = self.view().next_free_id(&self.me);
        true
    }

    /// Re-applies the pending entries on the confirmed replica; those that
    /// no longer apply are dropped and their author told why.
    fn rebase(&mut self) {
        if self.pending.is_empty() {
            self.view = None;
            return;
        }
        let mut view = self.confirmed.clone();
        let mut kept = VecDeque::new();
        for mut p in std::mem::take(&mut self.pending) {
            match view.apply_entry(&p.entry) {
                Ok(_) => {
                    p.sent = match p.sent {
                        Sent::Acked(s) => Sent::Acked(s),
                        _ => Sent::No,
                    };
                    kept.push_back(p);
                }
                Err(e) => self.notices.push(Notice {
                    author: self.me.clone(),
                    n: p.entry.n,
                    kind: NoticeKind::Refused,
                    message: format!("no longer applies after someone else's edit: {e}"),
                }),
            }
        }
        let _ = view.take_notices();
        self.pending = kept;
        self.view = if self.pending.is_empty() {
            None
        } else {
            Some(view)
        };
    }

    /// The next entry to append, if any may go now (one at a time after
    /// the last stored one, none while waiting out a conflict).
    pub fn next_publish(&mut self) -> Option<Publish> {
        if let Some(b) = self.blocked_at {
            if self.confirmed.last_seq() <= b {
                return None;
            }
            self.blocked_at = None;
        }
        let mut expected = self.confirmed.last_seq();
        for p in self.pending.iter_mut() {
            match p.sent {
                Sent::Acked(s) => expected = s,
                Sent::InFlight => return None,
                Sent::No => {
                    p.entry.base = expected;
                    p.sent = Sent::InFlight;
                    return Some(Publish {
                        n: p.entry.n,
                        msg_id: p.entry.msg_id(),
                        expected_last_seq: expected,
                        bytes: p.entry.to_bytes(),
                    });
                }
            }
        }
        None
    }

    /// Reports how the append of entry `n` ended.
    pub fn published(&mut self, n: u64, result: Published) {
        let Some(i) = self.pending.iter().position(|p| p.entry.n == n) else {
            return;
        };
        match result {
            Published::Stored(seq) => self.pending[i].sent = Sent::Acked(seq),
            Published::Conflict | Published::Failed => {
                if result == Published::Conflict {
                    // Wait until something newer than what the append
                    // expected has arrived (it may have already).
                    self.blocked_at = Some(self.pending[i].entry.base);
                }
                for p in self.pending.iter_mut().skip(i) {
                    if p.sent == Sent::InFlight {
                        p.sent = Sent::No;
                    }
                }
            }
        }
    }

    /// Sets how many entries pass between snapshots (default
    /// [`DEFAULT_SNAPSHOT_EVERY`]); every participant of a session must
    /// use the same.
    pub fn set_snapshot_every(&mut self, every: u64) {
        self.snapshot_every = every.max(1);
        self.snapshot_k = self.confirmed.last_seq() / self.snapshot_every;
    }

    /// A snapshot to store, when one is due: every
    /// [`Self::set_snapshot_every`] entries, the author of the first good
    /// entry past the boundary writes it (one writer per boundary).
    /// Returns the sequence it covers and its bytes.
    pub fn snapshot_due(&mut self) -> Option<(u64, Vec<u8>)> {
        if !std::mem::take(&mut self.snapshot_due) {
            return None;
        }
        Some((self.confirmed.last_seq(), self.confirmed.snapshot()))
    }

    /// True while an append conflicted and the entry that won has not
    /// arrived yet.
    pub fn is_blocked(&self) -> bool {
        self.blocked_at
            .is_some_and(|b| self.confirmed.last_seq() <= b)
    }

    /// Stops waiting out a conflict (the transport's fallback when no
    /// newer entry arrives in time, e.g. the stream was changed by hand).
    pub fn unblock(&mut self) {
        self.blocked_at = None;
    }

    /// Marks every in-flight append as not sent (the connection was lost;
    /// they go again, with the same message ids, on reconnect).
    pub fn connection_lost(&mut self) {
        for p in self.pending.iter_mut() {
            if p.sent == Sent::InFlight {
                p.sent = Sent::No;
            }
        }
    }

    /// The document as ordinary single-user history (the ops in effect,
    /// pending ones included), cursor at the end: what a shared session
    /// saves, and what opens in Blender. No replay: the document is taken
    /// as it is.
    pub fn linear_log(&self) -> Result<LinearLog, LogError> {
        let view = self.view();
        let ops = view.linear_ops();
        let n = ops.len();
        LinearLog::from_snapshot(ops, n, view.document().clone())
    }
}
