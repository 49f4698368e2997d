//! [`Replica`]: the document a stream of entries defines, the same on
//! every participant's machine. See the module doc of [`super`] for the
//! rules.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::MAX_PARTICIPANTS;
use super::{apply_op, id_from_token, id_range, subject_token, valid_author};
use super::{Body, Entry, ENTRY_VERSION, MAX_ENTRY_BYTES, OLDEST_ENTRY_VERSION};
use crate::doc::linear::thinned;
use crate::doc::{CheckpointPolicy, Document, LinearLog, Op, OpError, OpOutcome, ReserveIds};

mod snapshot;
pub use snapshot::SNAPSHOT_FORMAT;

/// Someone in the session.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Participant {
    /// Their participant id (the entries' `author`).
    pub id: String,
    /// The name shown to others.
    pub name: String,
    /// Their colour (linear RGB).
    pub colour: [f32; 3],
    /// Their id range (1 = the first to join).
    pub slot: u32,
    /// The highest entry counter of theirs applied.
    pub last_n: u64,
}

/// What a [`Notice`] tells an author.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoticeKind {
    /// Their entry was refused (invalid, a duplicate, or its op failed).
    Refused,
    /// An op of theirs no longer applies: an op it needed was undone.
    Skipped,
    /// A skipped op of theirs applies again (that op was redone).
    Restored,
    /// The snapshot they joined from differed from the stream's replay:
    /// their document is now the stream's (see [`super::SnapshotCheck`]).
    Replaced,
}

/// A message for one author about one of their entries.
#[derive(Clone, Debug, PartialEq)]
pub struct Notice {
    /// The author it is for.
    pub author: String,
    /// Their entry counter.
    pub n: u64,
    /// What happened.
    pub kind: NoticeKind,
    /// Why, for a person (the op's own error where there is one).
    pub message: String,
}

/// A stream message that was skipped, and why (every replica skips the
/// same ones for the same reason).
#[derive(Clone, Debug, PartialEq)]
pub struct Skipped {
    /// Its stream sequence.
    pub seq: u64,
    /// Why.
    pub reason: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
enum Effect {
    Applies { allocated: bool },
    Undone,
    Failed(String),
}

#[derive(Clone, Debug)]
struct OpRec {
    author: usize,
    n: u64,
    op: Arc<Op>,
    ids_from: Option<u32>,
    undone: bool,
    effect: Effect,
}

#[derive(Clone, Debug)]
struct Checkpoint {
    /// The document after the first `at` op records (in effect or not).
    at: usize,
    doc: Document,
}

/// The state a stream of entries defines: participants, every op with
/// whether it is undone or in effect, and the document.
#[derive(Clone, Debug)]
pub struct Replica {
    last_seq: u64,
    /// The newest entry version applied ([`ENTRY_VERSION`]'s rule).
    newest_version: u32,
    participants: Vec<Participant>,
    by_id: BTreeMap<String, usize>,
    /// Ops of a single-user document the session started from (the first
    /// entry may seed it), applied before any participant's.
    seed: Vec<Op>,
    ops: Vec<OpRec>,
    by_key: BTreeMap<(usize, u64), usize>,
    /// Per participant: their undone ops a redo may bring back, last
    /// undone last. Cleared by their next op.
    redo: Vec<Vec<u64>>,
    doc: Document,
    checkpoints: Vec<Checkpoint>,
    ops_since: usize,
    work_since: u64,
    policy: CheckpointPolicy,
    notices: Vec<Notice>,
    skipped: Vec<Skipped>,
    /// Ops re-applied by undos and redos (diagnostics: undo cost).
    replayed: u64,
}

impl Default for Replica {
    fn default() -> Self {
        Self::new()
    }
}

impl Replica {
    /// An empty session.
    pub fn new() -> Self {
        Self::with_policy(CheckpointPolicy::default())
    }

    /// An empty session with a given checkpoint policy (only speed
    /// depends on it).
    pub fn with_policy(policy: CheckpointPolicy) -> Self {
        Self {
            last_seq: 0,
            newest_version: OLDEST_ENTRY_VERSION,
            participants: Vec::new(),
            by_id: BTreeMap::new(),
            seed: Vec::new(),
            ops: Vec::new(),
            by_key: BTreeMap::new(),
            redo: Vec::new(),
            doc: Document::new(),
            checkpoints: vec![Checkpoint {
                at: 0,
                doc: Document::new(),
            }],
            ops_since: 0,
            work_since: 0,
            policy,
            notices: Vec::new(),
            skipped: Vec::new(),
            replayed: 0,
        }
    }

    /// The document at the last applied entry.
    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// The stream sequence of the last entry applied (0: none).
    pub fn last_seq(&self) -> u64 {
        self.last_seq
    }

    /// Everyone who joined, in joining order.
    pub fn participants(&self) -> &[Participant] {
        &self.participants
    }

    /// The participant with id `id`.
    pub fn participant(&self, id: &str) -> Option<&Participant> {
        self.by_id.get(id).map(|&i| &self.participants[i])
    }

    /// Number of op entries recorded (in effect, undone or failed).
    pub fn op_count(&self) -> usize {
        self.ops.len()
    }

    /// Number of checkpoints held.
    pub fn checkpoint_count(&self) -> usize {
        self.checkpoints.len()
    }

    /// Ops re-applied so far by undos and redos (each undo replays from
    /// the nearest checkpoint before the op it takes back).
    pub fn ops_replayed(&self) -> u64 {
        self.replayed
    }

    /// Messages skipped so far, with their reasons.
    pub fn skipped(&self) -> &[Skipped] {
        &self.skipped
    }

    /// Takes the notices gathered since the last call.
    pub fn take_notices(&mut self) -> Vec<Notice> {
        std::mem::take(&mut self.notices)
    }

    /// The op `author`'s undo takes back: their latest op in effect.
    pub fn undo_target(&self, author: &str) -> Option<u64> {
        let a = *self.by_id.get(author)?;
        self.ops
            .iter()
            .rev()
            .find(|r| r.author == a && matches!(r.effect, Effect::Applies { .. }))
            .map(|r| r.n)
    }

    /// The op `author`'s redo brings back: the last one they undid since
    /// their last op.
    pub fn redo_target(&self, author: &str) -> Option<u64> {
        let a = *self.by_id.get(author)?;
        self.redo[a].last().copied()
    }

    /// The first id `author` may take for a new creation: past every id
    /// any of their recorded ops reserved (so an undone creation's ids are
    /// never given to another object).
    pub fn next_free_id(&self, author: &str) -> Option<u32> {
        let a = *self.by_id.get(author)?;
        let (first, _) = id_range(self.participants[a].slot);
        let used = self
            .ops
            .iter()
            .filter(|r| r.author == a)
            .filter_map(|r| r.ids_from.map(|f| f + 1))
            .max()
            .unwrap_or(first);
        // Ids taken by ops in effect may run past ids_from + 1.
        let (_, end) = id_range(self.participants[a].slot);
        let taken = self
            .doc
            .objects()
            .map(|(id, _)| id.0)
            .filter(|&id| id >= first && id < end)
            .map(|id| id + 1)
            .max()
            .unwrap_or(first);
        Some(used.max(taken).max(first))
    }

    /// Applies the stream message `bytes` at sequence `seq`, which came on
    /// the subject of the person whose [`super::subject_token`] is `from`
    /// (the subject's last token). A message at or before the last
    /// sequence applied is ignored (a redelivery). A message that cannot
    /// apply is skipped, recorded in [`Self::skipped`], and its author
    /// (when known) gets a notice; an entry claiming an author other than
    /// the subject's person is refused, and both are told.
    /// Returns the entry's author and counter when it decoded, and the
    /// op's outcome or the reason it was refused.
    pub fn integrate(&mut self, seq: u64, from: &str, bytes: &[u8]) -> Integrated {
        if seq <= self.last_seq {
            return Integrated {
                key: None,
                result: Err(EntryError::Refused(format!(
                    "sequence {seq} was already applied (last {})",
                    self.last_seq
                ))),
                redelivery: true,
            };
        }
        self.last_seq = seq;
        let decoded = decode(bytes);
        let (key, result) = match decoded {
            Err(reason) => (None, Err(EntryError::Refused(reason))),
            Ok(entry) if subject_token(&entry.author).as_deref() != Some(from) => {
                (None, Err(self.impostor(&entry, from)))
            }
            Ok(entry) => {
                let key = Some((entry.author.clone(), entry.n));
                (key, self.apply_entry(&entry))
            }
        };
        if let Err(reason) = &result {
            self.skipped.push(Skipped {
                seq,
                reason: reason.to_string(),
            });
        }
        Integrated {
            key,
            result,
            redelivery: false,
        }
    }

    /// Moves the last applied sequence up to `seq` when the stream holds
    /// no messages between (nothing applies).
    pub(super) fn skip_to(&mut self, seq: u64) {
        self.last_seq = self.last_seq.max(seq);
    }

    /// Refuses `e`, sent on the subject of `from` but claiming another
    /// author: the sender and the person it claimed to be (when they are
    /// in the session) are told.
    fn impostor(&mut self, e: &Entry, from: &str) -> EntryError {
        let sender = id_from_token(from);
        let why = format!(
            "an entry claiming to be `{}`'s was sent on the subject of `{}`: only its author may send it",
            e.author.chars().take(80).collect::<String>(),
            sender.as_deref().unwrap_or(from).chars().take(80).collect::<String>(),
        );
        for who in [sender, Some(e.author.clone())].into_iter().flatten() {
            if self.by_id.contains_key(&who) {
                self.notices.push(Notice {
                    author: who,
                    n: e.n,
                    kind: NoticeKind::Refused,
                    message: why.clone(),
                });
            }
        }
        EntryError::Refused(why)
    }

    /// Why an entry of version `v` is not applied: a version this build
    /// does not read, or one older than the newest taken in
    /// ([`ENTRY_VERSION`]'s rule).
    fn check_version(&self, v: u32) -> Result<(), String> {
        if !(OLDEST_ENTRY_VERSION..=ENTRY_VERSION).contains(&v) {
            return Err(format!(
                "entry format version {v} (this build reads {OLDEST_ENTRY_VERSION} to \
                 {ENTRY_VERSION})"
            ));
        }
        if v < self.newest_version {
            return Err(format!(
                "made by an older Shapewright (entry version {v}) after a newer one \
                 (version {}) wrote to the session: the two compute some geometry \
                 differently, so the older build's edits are refused here; update \
                 Shapewright to go on editing together",
                self.newest_version
            ));
        }
        Ok(())
    }

    /// Applies one decoded entry (the stream's next). On error nothing but
    /// the author's entry counter changes.
    pub(super) fn apply_entry(&mut self, e: &Entry) -> Result<Option<OpOutcome>, EntryError> {
        let refuse = |this: &mut Self, reason: EntryError| {
            if this.by_id.contains_key(&e.author) {
                this.notices.push(Notice {
                    author: e.author.clone(),
                    n: e.n,
                    kind: NoticeKind::Refused,
                    message: reason.to_string(),
                });
            }
            Err(reason)
        };
        let refused = |reason: String| EntryError::Refused(reason);
        if let Err(why) = self.check_version(e.v) {
            return refuse(self, refused(why));
        }
        if !valid_author(&e.author) {
            return Err(refused(
                "author id is empty, longer than 64 bytes or not A-Z a-z 0-9 _ - .".into(),
            ));
        }
        if let Body::Join { name, colour } = &e.body {
            self.join(e, name, *colour).map_err(refused)?;
            self.newest_version = e.v;
            return Ok(None);
        }
        let Some(&a) = self.by_id.get(&e.author) else {
            return Err(refused(format!(
                "`{}` has not joined the session",
                e.author
            )));
        };
        if e.n <= self.participants[a].last_n {
            return refuse(
                self,
                refused(format!(
                    "duplicate: entry {} of `{}` was already applied",
                    e.n, e.author
                )),
            );
        }
        self.participants[a].last_n = e.n;
        // Only an entry taken in raises the version (a refused one, from
        // someone who never joined or a full session's joiner, does not).
        self.newest_version = e.v;
        match &e.body {
            Body::Join { .. } => unreachable!("handled above"),
            Body::Op { ids_from, op } => {
                let range = id_range(self.participants[a].slot);
                let mut next = self.doc.clone();
                let before = next.id_block();
                let result = apply_op(&mut next, op, *ids_from, range);
                self.redo[a].clear();
                let index = self.ops.len();
                self.by_key.insert((a, e.n), index);
                let (effect, out) = match result {
                    Ok(outcome) => {
                        let allocated = ids_from.is_some() && next.id_block() != before;
                        let cost = next.work() - self.doc.work();
                        self.doc = next;
                        self.ops_since += 1;
                        self.work_since += cost;
                        (Effect::Applies { allocated }, Ok(Some(outcome)))
                    }
                    Err(err) => {
                        self.ops_since += 1;
                        (Effect::Failed(err.to_string()), Err(err))
                    }
                };
                self.ops.push(OpRec {
                    author: a,
                    n: e.n,
                    op: Arc::new(op.clone()),
                    ids_from: *ids_from,
                    undone: false,
                    effect,
                });
                self.maybe_checkpoint();
                match out {
                    Ok(o) => Ok(o),
                    Err(err) => refuse(self, EntryError::Op(err)),
                }
            }
            Body::Undo(target) | Body::Redo(target) => {
                let undo = matches!(e.body, Body::Undo(_));
                let Some(&index) = self.by_key.get(&(a, *target)) else {
                    let verb = if undo { "undo" } else { "redo" };
                    return refuse(
                        self,
                        refused(format!("`{}` has no op {target} to {verb}", e.author)),
                    );
                };
                if self.ops[index].undone == undo {
                    let what = if undo { "already undone" } else { "not undone" };
                    return refuse(
                        self,
                        refused(format!("op {target} of `{}` is {what}", e.author)),
                    );
                }
                self.ops[index].undone = undo;
                if undo {
                    self.redo[a].push(*target);
                } else {
                    self.redo[a].retain(|n| n != target);
                }
                self.replay_from(index);
                Ok(None)
            }
            Body::Seed(ops) => {
                if !self.ops.is_empty() || !self.seed.is_empty() {
                    return refuse(
                        self,
                        refused("a seed must be the session's first op entry".into()),
                    );
                }
                let mut log = LinearLog::new();
                for op in ops {
                    if let Err(err) = log.apply(op.clone()) {
                        return refuse(
                            self,
                            refused(format!("the seed's op {} failed: {err}", log.len() + 1)),
                        );
                    }
                }
                self.seed = ops.clone();
                self.doc = log.document().clone();
                self.checkpoints = vec![Checkpoint {
                    at: 0,
                    doc: self.doc.clone(),
                }];
                Ok(None)
            }
        }
    }

    fn join(&mut self, e: &Entry, name: &str, colour: [f32; 3]) -> Result<(), String> {
        if name.len() > 64 || name.chars().any(char::is_control) {
            return Err(
                "a participant's name must be at most 64 bytes without control characters".into(),
            );
        }
        if colour
            .iter()
            .any(|c| !c.is_finite() || !(0.0..=1.0).contains(c))
        {
            return Err(format!(
                "colour {colour:?} is not linear RGB between 0 and 1"
            ));
        }
        if let Some(&a) = self.by_id.get(&e.author) {
            let p = &mut self.participants[a];
            if e.n <= p.last_n {
                return Err(format!(
                    "duplicate: entry {} of `{}` was already applied",
                    e.n, e.author
                ));
            }
            p.last_n = e.n;
            p.name = name.to_string();
            p.colour = colour;
            return Ok(());
        }
        if self.participants.len() as u32 >= MAX_PARTICIPANTS {
            return Err(format!(
                "the session is full ({MAX_PARTICIPANTS} participants)"
            ));
        }
        self.by_id.insert(e.author.clone(), self.participants.len());
        self.participants.push(Participant {
            id: e.author.clone(),
            name: name.to_string(),
            colour,
            slot: self.participants.len() as u32 + 1,
            last_n: e.n,
        });
        self.redo.push(Vec::new());
        Ok(())
    }

    /// Recomputes the document from the nearest checkpoint at or before op
    /// record `index` (whose undone flag changed), telling authors whose
    /// ops stop or start applying.
    fn replay_from(&mut self, index: usize) {
        self.checkpoints.retain(|c| c.at <= index);
        let cp = self.checkpoints.last().expect("the base checkpoint stays");
        let mut at = cp.at;
        let mut doc = cp.doc.clone();
        let (mut ops_since, mut work_since) = (0, 0);
        while at < self.ops.len() {
            let rec = &self.ops[at];
            let effect = if rec.undone {
                Effect::Undone
            } else {
                self.replayed += 1;
                let range = id_range(self.participants[rec.author].slot);
                let mut next = doc.clone();
                let before = next.id_block();
                match apply_op(&mut next, &rec.op, rec.ids_from, range) {
                    Ok(_) => {
                        let allocated = rec.ids_from.is_some() && next.id_block() != before;
                        work_since += next.work() - doc.work();
                        doc = next;
                        Effect::Applies { allocated }
                    }
                    Err(err) => Effect::Failed(err.to_string()),
                }
            };
            if at != index {
                self.note_change(at, &effect);
            }
            self.ops[at].effect = effect;
            at += 1;
            ops_since += 1;
            if ops_since >= self.policy.every_ops || work_since >= self.policy.every_work {
                self.checkpoints.push(Checkpoint {
                    at,
                    doc: doc.clone(),
                });
                ops_since = 0;
                work_since = 0;
            }
        }
        self.doc = doc;
        self.ops_since = ops_since;
        self.work_since = work_since;
        self.thin();
    }

    fn note_change(&mut self, at: usize, effect: &Effect) {
        let rec = &self.ops[at];
        let was = &rec.effect;
        let kind = match (was, effect) {
            (Effect::Applies { .. }, Effect::Failed(_)) => NoticeKind::Skipped,
            (Effect::Failed(_), Effect::Applies { .. }) => NoticeKind::Restored,
            _ => return,
        };
        let message = match (effect, kind) {
            (Effect::Failed(why), _) => {
                format!("no longer applies, since an op it needed was undone: {why}")
            }
            _ => "applies again: the op it needed was redone".to_string(),
        };
        self.notices.push(Notice {
            author: self.participants[rec.author].id.clone(),
            n: rec.n,
            kind,
            message,
        });
    }

    fn maybe_checkpoint(&mut self) {
        if self.ops_since >= self.policy.every_ops || self.work_since >= self.policy.every_work {
            self.checkpoints.push(Checkpoint {
                at: self.ops.len(),
                doc: self.doc.clone(),
            });
            self.ops_since = 0;
            self.work_since = 0;
            self.thin();
        }
    }

    fn thin(&mut self) {
        let ats: Vec<usize> = self.checkpoints.iter().map(|c| c.at).collect();
        let mut keep = thinned(&ats, &self.policy).into_iter();
        self.checkpoints.retain(|_| keep.next().unwrap_or(true));
    }

    /// The ops in effect as single-user history: the seed, then each op in
    /// effect in stream order, a creation preceded by its `reserve_ids`.
    /// Replayed from an empty document they give this document, bit for
    /// bit (what a shared session saves as USD).
    pub fn linear_ops(&self) -> Vec<Op> {
        let mut out = self.seed.clone();
        for r in &self.ops {
            if let Effect::Applies { allocated } = r.effect {
                if let (true, Some(first)) = (allocated, r.ids_from) {
                    out.push(Op::ReserveIds(ReserveIds { first }));
                }
                out.push((*r.op).clone());
            }
        }
        out
    }

    /// For each op entry in stream order: author, counter, and whether it
    /// is in effect (`Ok`), undone (`Err(None)`) or failed
    /// (`Err(Some(reason))`). For tests and the session's log.
    pub fn op_states(&self) -> Vec<(String, u64, Result<(), Option<String>>)> {
        self.ops
            .iter()
            .map(|r| {
                let state = match &r.effect {
                    Effect::Applies { .. } => Ok(()),
                    Effect::Undone => Err(None),
                    Effect::Failed(why) => Err(Some(why.clone())),
                };
                (self.participants[r.author].id.clone(), r.n, state)
            })
            .collect()
    }
}

/// Why an entry did not apply.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EntryError {
    /// Its op failed on the document (the document is unchanged).
    #[error(transparent)]
    Op(#[from] OpError),
    /// The entry itself was refused (see the module doc's list).
    #[error("{0}")]
    Refused(String),
}

/// What [`Replica::integrate`] did with one message.
#[derive(Clone, Debug, PartialEq)]
pub struct Integrated {
    /// The entry's author and counter, when it decoded.
    pub key: Option<(String, u64)>,
    /// The op's outcome (`None` for other entries), or why it was refused.
    pub result: Result<Option<OpOutcome>, EntryError>,
    /// True when the sequence was already applied (nothing changed).
    pub redelivery: bool,
}

fn decode(bytes: &[u8]) -> Result<Entry, String> {
    if bytes.len() > MAX_ENTRY_BYTES {
        return Err(format!(
            "message of {} bytes is larger than the {MAX_ENTRY_BYTES} an entry may be",
            bytes.len()
        ));
    }
    serde_json::from_slice(bytes).map_err(|e| format!("not an entry: {e}"))
}
