//! Assemblies of generalized cylinders (paper: "Interactive modeling of
//! man-made shapes by assembling generalized cylinders", §3.3; SPEC.md §1).
//!
//! The assembly graph lives in [`crate::gc::GcAssembly`]: nodes are GC
//! parts, an edge goes from a child to its parent, and each child stores
//! its [`Attachment`]: the surface parameters `(u, v)` on the parent's
//! side surface where its spine starts (and, for a handle, where it ends).
//! This module adds on top of it:
//!
//! - creating a child on its parent's surface at a picked point, sketched
//!   in the plane spanned by the parent's surface normal `n` and spine
//!   tangent `t` (spine plane normal `n x t`), its end free (a spout) or
//!   landing on the parent (a handle) ([`edits::GcAddChild`]);
//! - copying a part with its descendants, rigidly or mirrored about the
//!   parent's spine plane ([`edits::GcCopy`]);
//! - rigid transforms of a part whose descendants stay attached
//!   ([`edits::GcTransformPart`]);
//! - automatic detection of connectivity, coplanarity, concentricity and
//!   symmetry ([`detect_relations`]);
//! - relations recorded as parts are added ([`RecordedRelations`]:
//!   symmetric, coplanar, concentric) and structure-aware propagation of
//!   every GC edit through one path ([`propagate_edit`]): the part's
//!   recorded twins get the mirrored edit, then descendants breadth-first
//!   are re-placed on their parents' new surfaces, then every recorded
//!   relation is checked; an edit that would break one fails with
//!   [`AssemblyError::RelationBroken`] unless the user released it
//!   ([`GcRelease`]);
//! - the evaluated mesh of an assembly: the manifold union of its parts
//!   ([`union_mesh`], through `manifold-rust`), one closed 2-manifold.
//!
//! Choices: attachments are stored as surface parameters rather than
//! re-detected, because a re-placement must know where a child sat on the
//! *old* surface; a child follows its parent rigidly through the frame
//! `(n, t, n x t)` at its anchor (re-evaluated on the new surface), and a
//! handle's spine is then rotated and scaled about its start so its end
//! lands on its own anchor's new position. A slid or copied child turns
//! with the surface normal the same way. Relations are recorded when a
//! part is added, as the paper identifies them "by analyzing the assembly
//! procedure", rather than re-detected at each edit: a tolerance-based
//! re-detection loses a twin pair for good once rounding exceeds it, and
//! takes a copy lying on its source (a spout in its parent's spine plane
//! is its own mirror image) for its twin. Older documents without the
//! record get it detected once from their geometry
//! ([`ensure_recorded`]).

#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod anchor;
mod cache;
mod error;
mod junction;
mod propagate;
mod relations;
mod rigid;
mod structure;
mod union;

pub mod edits;

pub use crate::gc::{Anchor, Attachment, RecordedRelations};
pub use anchor::{
    anchor_frame, anchor_frame_in_plane, project_near, project_to_surface, Projection,
};
pub use cache::{CacheStats, UnionCache};
pub use edits::{ChildEnd, GcAddChild, GcCopy, GcEditPart, GcTransformPart, PartEdit};
pub use error::AssemblyError;
pub use junction::{BURY_MARGIN, MAX_SINK, RIM_SAMPLES};
pub use propagate::{descendants_bfs, reattach_descendants};
pub use relations::{
    children_of, detect_relations, spine_controls, spine_size, symmetry_twins, Relations,
};
pub use rigid::{flip_profile, mirror_gc, mirror_plane, reflect, transform_gc};
pub use structure::{
    check_relations, ensure_recorded, propagate_edit, record_new_part, GcRelease, MirrorEdit,
    RelationKind, RELATION_TOLERANCE,
};
pub use union::{union_mesh, union_mesh_cached};

#[cfg(test)]
mod tests;
