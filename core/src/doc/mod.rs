//! The document and its history.
//!
//! A [`Document`] holds objects keyed by stable [`ObjectId`]s. It changes
//! only through [`Op`] values applied by an [`OpLog`], which owns undo, redo,
//! the cursor, checkpoints and replay ([`LinearLog`] for one person, a
//! [`shared`] session for several). Every op is declared once, in
//! [`ops`]; [`schema`] describes them all for the hosts. Scripts of ops are
//! JSON lines ([`parse_script`]).
//!
//! Choices made here:
//! - **A new op after an undo drops the redo tail** (linear history, as in
//!   Blender and every DCC users know), rather than branching.
//! - **Atomic ops:** an op is applied to a copy of the document (objects are
//!   shared through `Arc`, so the copy costs one pointer per object) and the
//!   copy replaces the document only on success. A failed op therefore
//!   cannot leave a half-applied change, whatever module it comes from.
//! - **Checked at the door:** before it applies, every op's numbers are
//!   checked against its schema (finite, within the declared range), so a
//!   NaN from lost tracking or an `inf` from a host is refused with the
//!   field's name before any geometry code sees it.
//! - **Checkpoints** are whole-document snapshots (again `Arc`-shared), taken
//!   every [`CheckpointPolicy::every_ops`] ops or once the ops since the last
//!   one did [`CheckpointPolicy::every_work`] work, and thinned out with
//!   age (the newest [`CheckpointPolicy::dense`] kept, older ones at
//!   doubling gaps), so history memory grows with the log's logarithm.
//!   Undo restores the nearest checkpoint at or before the target and
//!   replays from it, so the cost of recent undos does not grow with the
//!   session; a far jump back replays one long gap once and leaves
//!   checkpoints behind it.

mod document;
mod error;
mod linear;
mod log;
mod object;
pub mod ops;
mod origin;
mod printable;
pub mod schema;
mod script;
pub mod shared;

pub use crate::hash::ContentHasher;
pub use crate::id::ObjectId;
pub use document::Document;
pub use error::{LogError, OpError};
pub use linear::{CheckpointPolicy, LinearLog};
pub use log::OpLog;
pub use object::{KindOf, Object, ObjectKind, Solid};
pub use ops::{
    AddSolid, Apply, Create, Delete, Duplicate, Edit, EditCx, EditSolid, ObjectCreate, ObjectEdit,
    Op, OpOutcome, RenameObject, ReserveIds, SetTransform, TransformBy, OP_KINDS, OP_NAMES,
};
pub use printable::{
    document_names, document_parts, document_size, print_document, print_document_scaled,
    print_document_with, print_status, PrintScale, ScaledPrint, FIT_RETRIES,
};
#[cfg(test)]
pub(crate) use script::applied;
pub use script::{
    parse_script, run_script, run_script_with, ScriptCommand, ScriptError, ScriptErrorKind,
    ScriptLine, OP_FORMAT_VERSION,
};
