//! [`Op`]: every change to a document, as a plain serde value with every
//! parameter explicit.
//!
//! On the wire an op is a JSON object whose `"op"` field names the variant
//! in snake case, e.g. `{"op":"add_solid","shape":{"kind":"sphere","radius":0.5}}`.
//! Fields with defaults may be left out of scripts; the log always records
//! them, so a recorded op never depends on defaults that may change.
//! [`OP_FORMAT_VERSION`] versions this encoding: new op kinds and new
//! optional fields keep the version; anything that changes the meaning of
//! an existing field bumps it.

use serde::{Deserialize, Serialize};

use super::{Document, ObjectId, ObjectKind, OpError, Solid};
use crate::math::{DQuat, DVec3, Transform};
use crate::solid::{SolidShape, DEFAULT_SEGMENTS};

/// The version of the op encoding this build writes and reads.
pub const OP_FORMAT_VERSION: u32 = 1;

/// The `"op"` names of every variant, in declaration order.
pub const OP_NAMES: &[&str] = &[
    "add_solid",
    "edit_solid",
    "set_transform",
    "transform_by",
    "duplicate",
    "delete",
    "gc_create",
    "gc_bend",
    "gc_replace_spine",
    "gc_resize",
    "gc_shift",
    "gc_twist",
    "gc_replace_section",
    "gc_delete_section",
    "gc_insert_section",
    "gc_set_shape",
    "gc_set_resolution",
    "gc_add_child",
    "gc_copy",
    "gc_transform_part",
    "gc_edit_part",
];

/// One change to a document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case")]
pub enum Op {
    /// Create a parametric solid.
    AddSolid(AddSolid),
    /// Change a solid's shape or resolution.
    EditSolid(EditSolid),
    /// Replace an object's placement.
    SetTransform(SetTransform),
    /// Apply a transform on top of an object's placement.
    TransformBy(TransformBy),
    /// Copy an object under a new id.
    Duplicate(Duplicate),
    /// Delete an object. Its id is never reused.
    Delete(Delete),
    /// Create a generalized-cylinder assembly with one part.
    GcCreate(crate::gc::ops::GcCreate),
    /// Bend a GC's spine by moving a key point.
    GcBend(crate::gc::ops::GcBend),
    /// Replace a GC's spine.
    GcReplaceSpine(crate::gc::ops::GcReplaceSpine),
    /// Resize a key section.
    GcResize(crate::gc::ops::GcResize),
    /// Shift a key section along the spine.
    GcShift(crate::gc::ops::GcShift),
    /// Twist a key section (propagated linearly).
    GcTwist(crate::gc::ops::GcTwist),
    /// Replace a key section.
    GcReplaceSection(crate::gc::ops::GcReplaceSection),
    /// Delete a key section.
    GcDeleteSection(crate::gc::ops::GcDeleteSection),
    /// Insert a key section (shape unchanged).
    GcInsertSection(crate::gc::ops::GcInsertSection),
    /// Set a GC's shape type and thickness.
    GcSetShape(crate::gc::ops::GcSetShape),
    /// Set a GC's mesh resolution.
    GcSetResolution(crate::gc::ops::GcSetResolution),
    /// Add a child GC starting on a part's surface.
    GcAddChild(crate::assembly::ops::GcAddChild),
    /// Copy a part with its descendants (optionally mirrored).
    GcCopy(crate::assembly::ops::GcCopy),
    /// Move a part rigidly; twins mirror it, children follow.
    GcTransformPart(crate::assembly::ops::GcTransformPart),
    /// Edit a part with structure-aware propagation.
    GcEditPart(crate::assembly::ops::GcEditPart),
}

/// What applying an op produced.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OpOutcome {
    /// The id of the object the op created, if it created one.
    pub created: Option<ObjectId>,
}

fn default_segments() -> u32 {
    DEFAULT_SEGMENTS
}

/// Create a parametric solid.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AddSolid {
    /// Shape and sizes.
    pub shape: SolidShape,
    /// Segments around each circle.
    #[serde(default = "default_segments")]
    pub segments: u32,
    /// Placement.
    #[serde(default)]
    pub transform: Transform,
}

/// Change a solid's shape (and resolution), keeping its placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EditSolid {
    /// The solid.
    pub id: ObjectId,
    /// New shape and sizes.
    pub shape: SolidShape,
    /// New segments around each circle.
    #[serde(default = "default_segments")]
    pub segments: u32,
}

/// Replace an object's placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SetTransform {
    /// The object.
    pub id: ObjectId,
    /// New placement.
    pub transform: Transform,
}

/// Apply `transform` after the object's current placement (in model space).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformBy {
    /// The object.
    pub id: ObjectId,
    /// The increment. A non-uniform scale is allowed only while the object
    /// is unrotated (otherwise the result would shear).
    pub transform: Transform,
}

/// Copy an object; the copy gets the next id.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Duplicate {
    /// The object to copy.
    pub id: ObjectId,
}

/// Delete an object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Delete {
    /// The object.
    pub id: ObjectId,
}

impl Op {
    /// The op's `"op"` name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::AddSolid(_) => "add_solid",
            Self::EditSolid(_) => "edit_solid",
            Self::SetTransform(_) => "set_transform",
            Self::TransformBy(_) => "transform_by",
            Self::Duplicate(_) => "duplicate",
            Self::Delete(_) => "delete",
            Self::GcCreate(_) => "gc_create",
            Self::GcBend(_) => "gc_bend",
            Self::GcReplaceSpine(_) => "gc_replace_spine",
            Self::GcResize(_) => "gc_resize",
            Self::GcShift(_) => "gc_shift",
            Self::GcTwist(_) => "gc_twist",
            Self::GcReplaceSection(_) => "gc_replace_section",
            Self::GcDeleteSection(_) => "gc_delete_section",
            Self::GcInsertSection(_) => "gc_insert_section",
            Self::GcSetShape(_) => "gc_set_shape",
            Self::GcSetResolution(_) => "gc_set_resolution",
            Self::GcAddChild(_) => "gc_add_child",
            Self::GcCopy(_) => "gc_copy",
            Self::GcTransformPart(_) => "gc_transform_part",
            Self::GcEditPart(_) => "gc_edit_part",
        }
    }

    /// Applies the op to `doc`. On error `doc` may be partly changed: call
    /// through [`super::OpLog::apply`], which applies to a copy.
    pub fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        match self {
            Self::AddSolid(op) => {
                let id = doc.insert(ObjectKind::Solid(Solid {
                    shape: op.shape,
                    segments: op.segments,
                    transform: op.transform,
                }))?;
                Ok(OpOutcome { created: Some(id) })
            }
            Self::EditSolid(op) => {
                let mut solid = solid_of(doc, op.id, "edit_solid")?;
                solid.shape = op.shape;
                solid.segments = op.segments;
                doc.replace(op.id, ObjectKind::Solid(solid))?;
                Ok(OpOutcome::default())
            }
            Self::SetTransform(op) => {
                op.transform.validate()?;
                let mut solid = solid_of(doc, op.id, "set_transform")?;
                solid.transform = op.transform;
                doc.replace(op.id, ObjectKind::Solid(solid))?;
                Ok(OpOutcome::default())
            }
            Self::TransformBy(op) => {
                let mut solid = solid_of(doc, op.id, "transform_by")?;
                solid.transform = compose(&op.transform, &solid.transform)?;
                doc.replace(op.id, ObjectKind::Solid(solid))?;
                Ok(OpOutcome::default())
            }
            Self::Duplicate(op) => {
                let kind = doc.get(op.id)?.kind.clone();
                let id = doc.insert(kind)?;
                Ok(OpOutcome { created: Some(id) })
            }
            Self::Delete(op) => {
                doc.remove(op.id)?;
                Ok(OpOutcome::default())
            }
            Self::GcCreate(op) => op.apply(doc),
            Self::GcBend(op) => op.apply(doc),
            Self::GcReplaceSpine(op) => op.apply(doc),
            Self::GcResize(op) => op.apply(doc),
            Self::GcShift(op) => op.apply(doc),
            Self::GcTwist(op) => op.apply(doc),
            Self::GcReplaceSection(op) => op.apply(doc),
            Self::GcDeleteSection(op) => op.apply(doc),
            Self::GcInsertSection(op) => op.apply(doc),
            Self::GcSetShape(op) => op.apply(doc),
            Self::GcSetResolution(op) => op.apply(doc),
            Self::GcAddChild(op) => op.apply(doc),
            Self::GcCopy(op) => op.apply(doc),
            Self::GcTransformPart(op) => op.apply(doc),
            Self::GcEditPart(op) => op.apply(doc),
        }
    }
}

fn solid_of(doc: &Document, id: ObjectId, op: &'static str) -> Result<Solid, OpError> {
    match &doc.get(id)?.kind {
        ObjectKind::Solid(s) => Ok(s.clone()),
        #[allow(unreachable_patterns)]
        other => Err(OpError::WrongKind {
            id,
            op,
            expected: "solid",
            found: other.name(),
        }),
    }
}

/// `outer` after `inner`, as one scale-rotate-translate transform.
fn compose(outer: &Transform, inner: &Transform) -> Result<Transform, OpError> {
    outer.validate()?;
    inner.validate()?;
    let s2 = DVec3::from_array(outer.scale);
    let r1 = DQuat::from_array(inner.rotate).normalize();
    let uniform = s2.x == s2.y && s2.y == s2.z;
    if !uniform
        && !r1.abs_diff_eq(DQuat::IDENTITY, 1e-12)
        && !r1.abs_diff_eq(-DQuat::IDENTITY, 1e-12)
    {
        return Err(OpError::ShearingScale { scale: outer.scale });
    }
    let r2 = DQuat::from_array(outer.rotate).normalize();
    // p -> t2 + R2 S2 (t1 + R1 S1 p) = (t2 + R2 S2 t1) + R2 R1 (S2' S1) p,
    // where S2' = S2 expressed in the inner frame (equal to S2 when S2 is
    // uniform or R1 is the identity).
    let t = DVec3::from_array(outer.translate) + r2 * (s2 * DVec3::from_array(inner.translate));
    let s = s2 * DVec3::from_array(inner.scale);
    let out = Transform {
        translate: t.to_array(),
        rotate: (r2 * r1).normalize().to_array(),
        scale: s.to_array(),
    };
    out.validate()?;
    Ok(out)
}
