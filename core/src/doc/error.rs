//! Errors of ops and of the log.

use super::ObjectId;
use crate::gc::GcError;
use crate::math::TransformError;
use crate::solid::SolidError;

/// Why an op could not be applied. The document is unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OpError {
    /// The op names an object that does not exist: it was deleted, or
    /// never created (ids start at 1 and are never reused).
    #[error("object {0} does not exist (deleted, or never created)")]
    BadId(ObjectId),
    /// A created object would take an id that is already in use (only a
    /// shared session's id ranges, placed by `reserve_ids`, can do that:
    /// a hostile or confused participant reusing someone's range).
    #[error("object id {0} is already in use; an object's id is never reused")]
    IdInUse(ObjectId),
    /// In a shared session, an op would create an object with an id outside
    /// its author's range (or without reserving one): refused so that ids
    /// made by different people can never collide.
    #[error("object id {0} is outside the id range of the op's author (shared session)")]
    IdOutsideRange(ObjectId),
    /// `reserve_ids` was given 0 or the largest id.
    #[error("ids cannot start at {0}: the first id of a block must be between 1 and 4294967294")]
    BadIdBlock(u32),
    /// The op needs another kind of object.
    #[error("object {id} is a {found}, but `{op}` needs a {expected}")]
    WrongKind {
        /// The object.
        id: ObjectId,
        /// The op's name.
        op: &'static str,
        /// The kind the op needs.
        expected: &'static str,
        /// The kind the object is.
        found: &'static str,
    },
    /// A field of the op is not finite, or outside the range its schema
    /// declares (see [`super::schema`]). Checked before anything is
    /// applied.
    #[error("`{op}`: field `{field}` {problem}")]
    BadField {
        /// The op's name.
        op: &'static str,
        /// The field's path in the op (`shape.radius`, `samples[3][1]`).
        field: String,
        /// What is wrong with it, with the allowed range.
        problem: String,
    },
    /// The name is too long or contains control characters.
    #[error("object name `{name}` is longer than {max} bytes or has control characters")]
    BadName {
        /// The start of the name.
        name: String,
        /// The longest name allowed, in bytes.
        max: usize,
    },
    /// A non-uniform scale applied on top of a rotation would shear the
    /// object, which a scale-rotate-translate placement cannot express.
    #[error("a non-uniform scale {scale:?} on top of a rotated placement would shear; scale before rotating, or edit the object's sizes")]
    ShearingScale {
        /// The scale asked for.
        scale: [f64; 3],
    },
    /// A transform is non-finite, singular or has a zero rotation.
    #[error(transparent)]
    Transform(#[from] TransformError),
    /// A solid's parameters are invalid.
    #[error(transparent)]
    Solid(#[from] SolidError),
    /// A generalized cylinder could not be built, edited or meshed.
    #[error(transparent)]
    Gc(#[from] GcError),
    /// A sculpt op's input is invalid.
    #[error(transparent)]
    Sculpt(#[from] crate::sculpt::SculptError),
    /// An SDF op failed.
    #[error(transparent)]
    Sdf(#[from] crate::sdf::SdfError),
    /// A styling op failed (curves, networks, surface tools).
    #[error(transparent)]
    Styling(#[from] crate::styling::StylingError),
    /// An assembly op failed, or the union of an assembly's parts.
    #[error(transparent)]
    Assembly(#[from] crate::assembly::AssemblyError),
    /// The edit would make its object not printable (it would pass through
    /// itself, refused under the document's self-intersection policy), or
    /// a print setting is out of range.
    #[error(transparent)]
    Print(#[from] crate::print::PrintError),
}

impl OpError {
    /// The error with the op's name filled in where the error names it.
    pub fn in_op(self, name: &'static str) -> Self {
        match self {
            Self::WrongKind {
                id,
                op: "",
                expected,
                found,
            } => Self::WrongKind {
                id,
                op: name,
                expected,
                found,
            },
            other => other,
        }
    }
}

/// Why the log could not do what was asked. The log and its document are
/// unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LogError {
    /// Undo at the start of history.
    #[error("nothing to undo")]
    NothingToUndo,
    /// Redo at the end of history.
    #[error("nothing to redo")]
    NothingToRedo,
    /// The op failed; see the inner error.
    #[error(transparent)]
    Op(#[from] OpError),
    /// Replaying recorded op `index` failed. Ops are deterministic, so this
    /// means the recorded history is not one this version can reproduce
    /// (a hand-edited or corrupted log).
    #[error("replaying op {index} of the history failed: {error}")]
    Replay {
        /// 0-based index of the op in the log.
        index: usize,
        /// What went wrong.
        error: OpError,
    },
    /// A shared session refused the action (see
    /// [`super::shared::SharedError`]).
    #[error("{0}")]
    Shared(String),
    /// A cursor past the end of the recorded ops.
    #[error("cursor {cursor} is past the {len} recorded ops")]
    BadCursor {
        /// The cursor asked for.
        cursor: usize,
        /// The number of ops.
        len: usize,
    },
}
