//! [`OpLog`]: the history a host holds, one person's ([`LinearLog`]) or
//! one participant's side of a shared session ([`SharedLog`]), behind one
//! interface: apply, undo, redo, the document, and the ops it saves.
//!
//! It only routes. The history itself lives in [`super::linear`] (cursor,
//! checkpoints, replay) and in [`super::shared`] (each person's own undo),
//! and both sit below this module: the shared session replays and saves
//! as a [`LinearLog`], never as an `OpLog` (issue 36 broke the circle the
//! two modules made when this file held both).

use std::sync::OnceLock;

use super::linear::{CheckpointPolicy, LinearLog};
use super::shared::SharedLog;
use super::{Document, LogError, Op, OpOutcome};

/// The history of a document: recorded ops, a cursor (how many of them are
/// applied), the current document and checkpoints; or, in a shared
/// session, that session as this participant sees it.
#[derive(Clone, Debug)]
pub struct OpLog {
    /// The single-user history; unused (empty) while `shared` is set.
    linear: LinearLog,
    /// A shared session (issue 23), when this log is one participant's
    /// side of it: the document, apply, undo and redo are the session's
    /// (per person); the ops are its single-user history.
    shared: Option<Box<SharedLog>>,
    /// The shared session's single-user history, made when first asked
    /// for after a change (saving asks; frames do not).
    shared_ops: OnceLock<Vec<Op>>,
}

impl Default for OpLog {
    fn default() -> Self {
        Self::new()
    }
}

impl From<LinearLog> for OpLog {
    fn from(linear: LinearLog) -> Self {
        Self {
            linear,
            shared: None,
            shared_ops: OnceLock::new(),
        }
    }
}

impl OpLog {
    /// An empty history over an empty document.
    pub fn new() -> Self {
        LinearLog::new().into()
    }

    /// An empty history with a given checkpoint policy.
    pub fn with_policy(policy: CheckpointPolicy) -> Self {
        LinearLog::with_policy(policy).into()
    }

    /// A log that is one participant's side of a shared session: edits,
    /// undo and redo go to `shared` (each person undoes their own ops),
    /// and the history it reports and saves is the session's document as
    /// single-user ops ([`SharedLog::linear_log`]).
    pub fn from_shared(shared: SharedLog) -> Self {
        let mut log = Self::new();
        log.shared = Some(Box::new(shared));
        log
    }

    /// Replays `ops` from an empty document and leaves the cursor at
    /// `cursor` (the ops after it stay available to redo).
    pub fn replay(ops: Vec<Op>, cursor: usize) -> Result<Self, LogError> {
        LinearLog::replay(ops, cursor).map(Self::from)
    }

    /// Rebuilds a log from its ops, cursor and the document at the cursor
    /// (as a saved file stores them), without replaying: see
    /// [`LinearLog::from_snapshot`].
    pub fn from_snapshot(ops: Vec<Op>, cursor: usize, doc: Document) -> Result<Self, LogError> {
        LinearLog::from_snapshot(ops, cursor, doc).map(Self::from)
    }

    /// The shared session, if this log is part of one.
    pub fn shared(&self) -> Option<&SharedLog> {
        self.shared.as_deref()
    }

    /// Runs `f` on the shared session (a host's network pump: entries
    /// arriving, appends going out). `None` when the log is not shared.
    pub fn with_shared<R>(&mut self, f: impl FnOnce(&mut SharedLog) -> R) -> Option<R> {
        let s = self.shared.as_deref_mut()?;
        let r = f(s);
        self.shared_ops = OnceLock::new();
        Some(r)
    }

    /// The document at the cursor.
    pub fn document(&self) -> &Document {
        match &self.shared {
            Some(s) => s.document(),
            None => self.linear.document(),
        }
    }

    /// Every recorded op, including the redo tail past the cursor (in a
    /// shared session: the session's document as single-user ops).
    pub fn ops(&self) -> &[Op] {
        match &self.shared {
            Some(s) => self.shared_ops.get_or_init(|| s.view().linear_ops()),
            None => self.linear.ops(),
        }
    }

    /// How many ops are applied.
    pub fn cursor(&self) -> usize {
        match &self.shared {
            Some(_) => self.ops().len(),
            None => self.linear.cursor(),
        }
    }

    /// Number of recorded ops.
    pub fn len(&self) -> usize {
        self.ops().len()
    }

    /// True when no op was recorded.
    pub fn is_empty(&self) -> bool {
        self.ops().is_empty()
    }

    /// True when there is an op to undo.
    pub fn can_undo(&self) -> bool {
        match &self.shared {
            Some(s) => s.can_undo(),
            None => self.linear.can_undo(),
        }
    }

    /// True when there is an op to redo.
    pub fn can_redo(&self) -> bool {
        match &self.shared {
            Some(s) => s.can_redo(),
            None => self.linear.can_redo(),
        }
    }

    /// Number of checkpoints held (for tests and diagnostics; in a shared
    /// session, those of the confirmed replica).
    pub fn checkpoint_count(&self) -> usize {
        match &self.shared {
            Some(s) => s.confirmed().checkpoint_count(),
            None => self.linear.checkpoint_count(),
        }
    }

    /// Applies `op` at the cursor. On success the redo tail is dropped and
    /// `op` is recorded; on error nothing changes.
    pub fn apply(&mut self, op: Op) -> Result<OpOutcome, LogError> {
        if self.shared.is_some() {
            return Ok(self.with_shared(|s| s.apply(op)).expect("shared")?);
        }
        self.linear.apply(op)
    }

    /// Steps the cursor back one op.
    pub fn undo(&mut self) -> Result<(), LogError> {
        if self.shared.is_some() {
            return Ok(self.with_shared(|s| s.undo()).expect("shared")?);
        }
        self.linear.undo()
    }

    /// Re-applies the op after the cursor.
    pub fn redo(&mut self) -> Result<(), LogError> {
        if self.shared.is_some() {
            return Ok(self.with_shared(|s| s.redo()).expect("shared")?);
        }
        self.linear.redo()
    }

    /// Moves the cursor to `target` (0..=len), undoing or redoing as many
    /// ops as needed. On error nothing changes. A shared session has no
    /// single cursor, so it refuses.
    pub fn seek(&mut self, target: usize) -> Result<(), LogError> {
        if self.shared.is_some() {
            return Err(LogError::Shared(
                "a shared session has no single cursor: each person undoes and redoes their own ops".into(),
            ));
        }
        self.linear.seek(target)
    }
}
