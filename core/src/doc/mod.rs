//! The document and its history.
//!
//! A [`Document`] holds objects keyed by stable [`ObjectId`]s. It changes
//! only through [`Op`] values applied by an [`OpLog`], which owns undo, redo,
//! the cursor, checkpoints and replay. Scripts of ops are JSON lines
//! ([`parse_script`]).
//!
//! Choices made here:
//! - **A new op after an undo drops the redo tail** (linear history, as in
//!   Blender and every DCC users know), rather than branching.
//! - **Atomic ops:** an op is applied to a copy of the document (objects are
//!   shared through `Arc`, so the copy costs one pointer per object) and the
//!   copy replaces the document only on success. A failed op therefore
//!   cannot leave a half-applied change, whatever module it comes from.
//! - **Checkpoints** are whole-document snapshots (again `Arc`-shared), taken
//!   every [`CheckpointPolicy::every_ops`] ops or once the ops since the last
//!   one did [`CheckpointPolicy::every_work`] work. Undo restores the
//!   nearest checkpoint at or before the target and replays at most that
//!   many ops, so its cost does not grow with the session.

mod document;
mod error;
mod hash;
mod id;
mod log;
mod object;
mod op;
mod script;

pub use document::Document;
pub use error::{LogError, OpError};
pub use hash::ContentHasher;
pub use id::ObjectId;
pub use log::{CheckpointPolicy, OpLog};
pub use object::{Object, ObjectKind, Solid};
pub use op::{
    AddSolid, Delete, Duplicate, EditSolid, Op, OpOutcome, SetTransform, TransformBy,
    OP_FORMAT_VERSION, OP_NAMES,
};
pub use script::{
    parse_script, run_script, ScriptCommand, ScriptError, ScriptErrorKind, ScriptLine,
};
