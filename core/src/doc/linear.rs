//! [`LinearLog`]: one linear history of ops with a cursor, undo, redo,
//! replay and checkpoints. See the module doc of [`crate::doc`] for the
//! choices.
//!
//! This is the engine under [`super::OpLog`] when one person edits, and
//! what a shared session ([`super::shared`]) replays its seed with and
//! saves as. It knows nothing of shared sessions: [`super::OpLog`] routes
//! to either, so this module and `shared/` build on each other in one
//! direction only (issue 36).

use super::schema::check_op;
use super::{Document, LogError, Op, OpOutcome};

/// When the log takes a checkpoint (a snapshot of the document). Only
/// speed depends on this, never the document's content.
#[derive(Clone, Copy, Debug)]
pub struct CheckpointPolicy {
    /// Take a checkpoint at least every this many ops.
    pub every_ops: usize,
    /// Take a checkpoint once the ops since the last one did this much
    /// work (triangles meshed, see [`Document::work`]), so undo never
    /// replays more than about this much. Work, not wall time, keeps the
    /// checkpoint positions deterministic.
    pub every_work: u64,
    /// How many of the newest checkpoints are always kept as taken. Older
    /// ones are thinned out so that, walking back in time, each kept one
    /// is at least twice as far from the next newer kept one as the
    /// previous gap ([`LinearLog::apply`]): memory grows with the log's
    /// logarithm, not its length (issue 21), and undo stays flat over the
    /// last `dense` intervals. Undoing farther back replays one longer gap
    /// once and leaves checkpoints behind, so the undos after it are
    /// bounded again.
    pub dense: usize,
}

impl Default for CheckpointPolicy {
    fn default() -> Self {
        Self {
            every_ops: 32,
            every_work: 400_000,
            dense: 8,
        }
    }
}

#[derive(Clone, Debug)]
struct Checkpoint {
    /// The document after the first `at` ops.
    at: usize,
    doc: Document,
}

/// The history of a document as one person makes it: recorded ops, a
/// cursor (how many of them are applied), the current document and
/// checkpoints.
#[derive(Clone, Debug)]
pub struct LinearLog {
    ops: Vec<Op>,
    cursor: usize,
    doc: Document,
    checkpoints: Vec<Checkpoint>,
    /// States passed through by the last backward replay, so a run of
    /// undos replays once per checkpoint interval, not once per undo.
    /// Cleared when history changes.
    window: Vec<Checkpoint>,
    ops_since: usize,
    work_since: u64,
    policy: CheckpointPolicy,
}

impl Default for LinearLog {
    fn default() -> Self {
        Self::new()
    }
}

impl LinearLog {
    /// An empty history over an empty document.
    pub fn new() -> Self {
        Self::with_policy(CheckpointPolicy::default())
    }

    /// An empty history with a given checkpoint policy.
    pub fn with_policy(policy: CheckpointPolicy) -> Self {
        Self {
            ops: Vec::new(),
            cursor: 0,
            doc: Document::new(),
            checkpoints: vec![Checkpoint {
                at: 0,
                doc: Document::new(),
            }],
            window: Vec::new(),
            ops_since: 0,
            work_since: 0,
            policy,
        }
    }

    /// Replays `ops` from an empty document and leaves the cursor at
    /// `cursor` (the ops after it stay available to redo).
    pub fn replay(ops: Vec<Op>, cursor: usize) -> Result<Self, LogError> {
        check_cursor(cursor, ops.len())?;
        check_all(&ops)?;
        let mut log = Self::new();
        log.ops = ops;
        log.seek(cursor)?;
        Ok(log)
    }

    /// Rebuilds a log from its ops, cursor and the document at the cursor
    /// (as a saved file stores them), without replaying: reopening costs
    /// what the document costs, not what the history does. The first undo
    /// then replays from the start once and leaves checkpoints behind, so
    /// later undos are bounded again.
    pub fn from_snapshot(ops: Vec<Op>, cursor: usize, doc: Document) -> Result<Self, LogError> {
        check_cursor(cursor, ops.len())?;
        check_all(&ops)?;
        let mut log = Self::new();
        log.ops = ops;
        log.cursor = cursor;
        if cursor > 0 {
            log.checkpoints.push(Checkpoint {
                at: cursor,
                doc: doc.clone(),
            });
        }
        log.doc = doc;
        Ok(log)
    }

    /// The document at the cursor.
    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// Every recorded op, including the redo tail past the cursor.
    pub fn ops(&self) -> &[Op] {
        &self.ops
    }

    /// How many ops are applied.
    pub fn cursor(&self) -> usize {
        self.cursor
    }

    /// Number of recorded ops.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// True when no op was recorded.
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// True when there is an op to undo.
    pub fn can_undo(&self) -> bool {
        self.cursor > 0
    }

    /// True when there is an op to redo.
    pub fn can_redo(&self) -> bool {
        self.cursor < self.ops.len()
    }

    /// Number of checkpoints held (for tests and diagnostics).
    pub fn checkpoint_count(&self) -> usize {
        self.checkpoints.len()
    }

    /// Applies `op` at the cursor. On success the redo tail is dropped and
    /// `op` is recorded; on error nothing changes.
    pub fn apply(&mut self, op: Op) -> Result<OpOutcome, LogError> {
        check_op(&op)?;
        let mut next = self.doc.clone();
        let outcome = op.apply(&mut next)?;
        let cost = next.work() - self.doc.work();
        self.ops.truncate(self.cursor);
        self.checkpoints.retain(|c| c.at <= self.cursor);
        self.window.clear();
        self.ops.push(op);
        self.cursor += 1;
        self.doc = next;
        self.note_progress(cost);
        Ok(outcome)
    }

    /// Steps the cursor back one op.
    pub fn undo(&mut self) -> Result<(), LogError> {
        if self.cursor == 0 {
            return Err(LogError::NothingToUndo);
        }
        self.seek(self.cursor - 1)
    }

    /// Re-applies the op after the cursor.
    pub fn redo(&mut self) -> Result<(), LogError> {
        if self.cursor == self.ops.len() {
            return Err(LogError::NothingToRedo);
        }
        self.seek(self.cursor + 1)
    }

    /// Moves the cursor to `target` (0..=len), undoing or redoing as many
    /// ops as needed. On error nothing changes.
    pub fn seek(&mut self, target: usize) -> Result<(), LogError> {
        check_cursor(target, self.ops.len())?;
        if target == self.cursor {
            return Ok(());
        }
        if let Some(c) = self.window.iter().find(|c| c.at == target) {
            let (ops_since, work_since) = self.distance_from_checkpoint(target);
            self.doc = c.doc.clone();
            self.cursor = target;
            self.ops_since = ops_since;
            self.work_since = work_since;
            return Ok(());
        }
        // Start from the latest state at or before the target that we hold:
        // the current document when moving forward, else a checkpoint.
        let cp = self
            .checkpoints
            .iter()
            .rposition(|c| c.at <= target)
            .expect("checkpoint 0 always exists");
        let (mut at, mut doc, mut ops_since, mut work_since) =
            if target > self.cursor && self.cursor >= self.checkpoints[cp].at {
                (
                    self.cursor,
                    self.doc.clone(),
                    self.ops_since,
                    self.work_since,
                )
            } else {
                let c = &self.checkpoints[cp];
                (c.at, c.doc.clone(), 0, 0)
            };
        let backward = target < self.cursor;
        let mut new_checkpoints = Vec::new();
        let mut window = Vec::new();
        while at < target {
            let before = doc.work();
            self.ops[at]
                .apply(&mut doc)
                .map_err(|error| LogError::Replay { index: at, error })?;
            at += 1;
            ops_since += 1;
            work_since += doc.work() - before;
            if self.wants_checkpoint(ops_since, work_since) {
                new_checkpoints.push(Checkpoint {
                    at,
                    doc: doc.clone(),
                });
                ops_since = 0;
                work_since = 0;
            }
            if backward {
                window.push(Checkpoint {
                    at,
                    doc: doc.clone(),
                });
            }
        }
        if backward {
            window.push(Checkpoint {
                at: self.cursor,
                doc: self.doc.clone(),
            });
            self.window = window;
        }
        for c in new_checkpoints {
            self.insert_checkpoint(c);
        }
        self.cursor = target;
        self.doc = doc;
        self.ops_since = ops_since;
        self.work_since = work_since;
        Ok(())
    }

    /// Ops and work between the last checkpoint at or before `at` and `at`
    /// (work is not known for states restored from the window; 0 then,
    /// which only delays the next checkpoint by the op count).
    fn distance_from_checkpoint(&self, at: usize) -> (usize, u64) {
        let last = self
            .checkpoints
            .iter()
            .rfind(|c| c.at <= at)
            .map_or(0, |c| c.at);
        (at - last, 0)
    }

    fn wants_checkpoint(&self, ops: usize, work: u64) -> bool {
        ops >= self.policy.every_ops || work >= self.policy.every_work
    }

    fn note_progress(&mut self, work: u64) {
        self.ops_since += 1;
        self.work_since += work;
        if self.wants_checkpoint(self.ops_since, self.work_since) {
            self.insert_checkpoint(Checkpoint {
                at: self.cursor,
                doc: self.doc.clone(),
            });
            self.ops_since = 0;
            self.work_since = 0;
            self.thin_checkpoints();
        }
    }

    /// Drops old checkpoints (see [`CheckpointPolicy::dense`]); the one at
    /// 0 always stays. Depends only on op positions: deterministic.
    fn thin_checkpoints(&mut self) {
        let ats: Vec<usize> = self.checkpoints.iter().map(|c| c.at).collect();
        let mut k = thinned(&ats, &self.policy).into_iter();
        self.checkpoints.retain(|_| k.next().unwrap_or(true));
    }

    fn insert_checkpoint(&mut self, c: Checkpoint) {
        match self.checkpoints.binary_search_by_key(&c.at, |x| x.at) {
            Ok(_) => {}
            Err(pos) => self.checkpoints.insert(pos, c),
        }
    }
}

/// Which of the checkpoints at op positions `ats` (ascending, the first
/// being the base) to keep: the base, the newest `policy.dense`, and older
/// ones at doubling gaps walking back in time (see
/// [`CheckpointPolicy::dense`]). Shared by [`LinearLog`] and the shared
/// session's replica.
pub(super) fn thinned(ats: &[usize], policy: &CheckpointPolicy) -> Vec<bool> {
    let n = ats.len();
    let dense = policy.dense.max(1);
    if n <= dense + 1 {
        return vec![true; n];
    }
    let mut keep = vec![false; n];
    keep[0] = true;
    for k in keep.iter_mut().skip(n - dense) {
        *k = true;
    }
    let mut last = ats[n - dense];
    let mut gap = 2 * policy.every_ops.max(1);
    for i in (1..n - dense).rev() {
        if last - ats[i] >= gap {
            keep[i] = true;
            last = ats[i];
            gap = gap.saturating_mul(2);
        }
    }
    keep
}

/// Every recorded op passes the door check (a file's ops too, not only
/// those applied live).
fn check_all(ops: &[Op]) -> Result<(), LogError> {
    for (index, op) in ops.iter().enumerate() {
        check_op(op).map_err(|error| LogError::Replay { index, error })?;
    }
    Ok(())
}

/// A cursor may sit anywhere from before the first op to after the last.
fn check_cursor(cursor: usize, len: usize) -> Result<(), LogError> {
    if cursor > len {
        return Err(LogError::BadCursor { cursor, len });
    }
    Ok(())
}
