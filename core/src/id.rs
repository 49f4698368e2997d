//! The stable id of a document object.
//!
//! It lives below every module (not in `doc`) because a few geometry values
//! carry a reference to another object that the document resolves before
//! the geometry code runs (a sculpt brush or base made from "that object's
//! mesh"): those values hold an [`ObjectId`] as an opaque handle and never
//! look it up themselves.

use serde::{Deserialize, Serialize};

/// The stable id of a document object. Ids are allocated by the log in
/// order, starting at 1, and never reused, so a replay allocates the same
/// ids and a script can name the objects it created.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    schemars::JsonSchema,
)]
#[serde(transparent)]
#[schemars(extend("x-ref" = "object"))]
pub struct ObjectId(pub u32);

impl std::fmt::Display for ObjectId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{}", self.0)
    }
}
