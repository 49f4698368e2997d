//! What the generalized-cylinder tool shows ([`GcPreview`]) and what its
//! ray selects ([`GcTarget`]). Here, on the preview side, so that
//! [`super::ToolPreview`] names them without the preview importing the
//! tool that fills them (issue 36).

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::doc::ObjectId;
use crate::gc::Profile;
use crate::math::DVec3;
use crate::mesh::TriMesh;

use crate::interact::gesture::similarity::Similarity;

/// What a ray selects (model space).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum GcTarget {
    /// A spine key point (the centre of key section `section`).
    KeyPoint {
        /// The assembly object.
        id: ObjectId,
        /// The part.
        part: usize,
        /// The section whose centre it is.
        section: usize,
        /// The key point.
        point: DVec3,
    },
    /// A key section (curve), hit at `point`.
    Section {
        /// The assembly object.
        id: ObjectId,
        /// The part.
        part: usize,
        /// The section.
        section: usize,
        /// The hit point.
        point: DVec3,
    },
    /// The side surface of a part, away from its key sections.
    Surface {
        /// The assembly object.
        id: ObjectId,
        /// The part.
        part: usize,
        /// The point on the exact surface nearest the hit.
        point: DVec3,
        /// Its spine parameter.
        v: f64,
    },
    /// Nothing: a point in empty space.
    Empty {
        /// The point.
        point: DVec3,
    },
}

impl GcTarget {
    /// The selected point.
    pub fn point(&self) -> DVec3 {
        match *self {
            Self::KeyPoint { point, .. }
            | Self::Section { point, .. }
            | Self::Surface { point, .. }
            | Self::Empty { point } => point,
        }
    }

    /// The object and part, if a part is selected.
    pub fn part(&self) -> Option<(ObjectId, usize)> {
        match *self {
            Self::KeyPoint { id, part, .. }
            | Self::Section { id, part, .. }
            | Self::Surface { id, part, .. } => Some((id, part)),
            Self::Empty { .. } => None,
        }
    }

    /// Same element (ignoring where exactly it was hit).
    pub fn same_element(&self, other: &GcTarget) -> bool {
        match (self, other) {
            (
                Self::KeyPoint {
                    id, part, section, ..
                },
                Self::KeyPoint {
                    id: i2,
                    part: p2,
                    section: s2,
                    ..
                },
            )
            | (
                Self::Section {
                    id, part, section, ..
                },
                Self::Section {
                    id: i2,
                    part: p2,
                    section: s2,
                    ..
                },
            ) => id == i2 && part == p2 && section == s2,
            (
                Self::Surface { id, part, .. },
                Self::Surface {
                    id: i2, part: p2, ..
                },
            ) => id == i2 && part == p2,
            (Self::Empty { .. }, Self::Empty { .. }) => true,
            _ => false,
        }
    }
}

/// GC-specific preview state (part of [`Preview`](crate::interact::Preview)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GcPreview {
    /// The state machine's state (`idle`, `placed`, `sketch_section`, ...).
    pub mode: &'static str,
    /// The element under the ray (or being edited).
    pub target: Option<GcTarget>,
    /// Progress of a 3 s hold in `[0, 1]`.
    pub hold: f64,
    /// The sketch plane (origin, normal; model space) while sketching.
    pub plane: Option<(DVec3, DVec3)>,
    /// The matched section of a part being created.
    pub profile: Option<Profile>,
    /// The edited part as it would be if the gesture ended now (model
    /// space, preview resolution).
    pub mesh: Option<Arc<TriMesh>>,
    /// The whole-shape view transform on top of the session's placement
    /// (world to world), when not the identity.
    pub view: Option<Similarity>,
}
