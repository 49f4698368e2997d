//! Typed ids of document objects.

use serde::{Deserialize, Serialize};

/// The stable id of a document object. Ids are allocated by the log in
/// order, starting at 1, and never reused, so a replay allocates the same
/// ids and a script can name the objects it created.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ObjectId(pub u32);

impl std::fmt::Display for ObjectId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{}", self.0)
    }
}
