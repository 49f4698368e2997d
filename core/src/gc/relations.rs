//! [`RecordedRelations`]: the relations between an assembly's parts as
//! they were recorded when the parts were added, stored in the GC model.
//! Recording and checking them is [`crate::assembly`]'s work; only the
//! record lives here, so the model names nothing above it.

use serde::{Deserialize, Serialize};

/// Relations recorded between the parts of an assembly, each pair
/// `(i, j)` with `i < j`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RecordedRelations {
    /// Same parent, mirror images about the parent's spine plane.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub symmetric: Vec<(usize, usize)>,
    /// Spines in one plane.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub coplanar: Vec<(usize, usize)>,
    /// Parent and child with straight spines on one line.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub concentric: Vec<(usize, usize)>,
}

impl RecordedRelations {
    /// The recorded twins of `part`.
    pub fn twins_of(&self, part: usize) -> Vec<usize> {
        self.symmetric
            .iter()
            .filter_map(|&(a, b)| {
                if a == part {
                    Some(b)
                } else if b == part {
                    Some(a)
                } else {
                    None
                }
            })
            .collect()
    }
}
