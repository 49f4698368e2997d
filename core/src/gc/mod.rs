//! Generalized cylinders (paper: "Interactive modeling of man-made shapes
//! by assembling generalized cylinders", §3.1-3.2; SPEC.md §1).
//!
//! A [`Gc`] is a planar spine, key sections placed on it by
//! rotation-minimizing frames ([`crate::math::frames`]), and the NURBS
//! surface skinned exactly through them ([`crate::nurbs::skin`]). Shape
//! types solid / shell / container with thickness τ mesh to closed,
//! oriented 2-manifolds ([`mesh_gc`]). The edits of §3.2 (bend, replace
//! spine, resize, shift, twist, replace, delete, insert) are methods
//! on [`Gc`]; their op payloads ([`edits`]: what to do to which part and
//! section) are plain values the document applies to the object kind
//! [`GcAssembly`].
//!
//! [`budget`] bounds the sections, skinning work and mesh grid of one GC
//! (issue 22); [`Gc::validate`] applies it.
//!
//! Choices: sections are stored in their local frames (profile, scale,
//! twist, spine parameter) and placed at evaluation, so spine edits
//! re-frame them, as the paper's bend does; the `v`-interpolation is
//! natural cubic at the sections' spine parameters so an inserted
//! iso-curve leaves the surface unchanged (checked to 1e-9 in tests).

#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod assembly;
mod attachment;
pub mod budget;
pub mod edits;
mod error;
mod mesh;
mod model;
mod relations;
mod reshape;
mod section;

pub use assembly::{GcAssembly, GcPart};
pub use attachment::{Anchor, Attachment};
pub use edits::{
    build_gc, edit_part_gc, GcBend, GcCreate, GcDeleteSection, GcEdit, GcInsertSection,
    GcReplaceSection, GcReplaceSpine, GcResize, GcSetResolution, GcSetShape, GcShift, GcTwist,
    PartId, SectionIndex, SectionSpec,
};
pub use error::GcError;
pub use mesh::{cavity_gc, inscribed_radius, mesh_gc, samples_between};
pub use model::{
    fit_spine, ClosedEnd, Gc, Resolution, ShapeType, Spine, SpineFrames, MAX_SPINE_POINTS,
    RMF_STEPS,
};
pub use relations::RecordedRelations;
pub use section::{loop_self_intersects, signed_area, KeySection, Profile, MAX_CURVE_DEGREE};

#[cfg(test)]
mod tests;
