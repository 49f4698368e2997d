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
use crate::styling;

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
    "sculpt_create",
    "sculpt_stroke",
    "sdf_create",
    "sdf_add_operand",
    "sdf_set_operand_transform",
    "sdf_scale_two_hand",
    "sdf_cancel_operand",
    "sdf_copy_operand",
    "sdf_update",
    "sdf_import_component",
    "sdf_set_step",
    "curve_network_create",
    "curve_draw",
    "curve_smooth",
    "curve_sharpen",
    "curve_pull",
    "curve_delete",
    "curve_fill_loop",
    "curve_fill_auto",
    "surface_smooth",
    "surface_sharpen",
    "surface_pull",
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
    /// Create a sculpt object from a base shape or a closed mesh.
    SculptCreate(crate::sculpt::SculptCreate),
    /// Apply one warp-brush stroke to a sculpt object.
    SculptStroke(crate::sculpt::SculptStroke),
    /// `sdf_create`: see [`crate::sdf::ops`].
    SdfCreate(crate::sdf::ops::SdfCreate),
    /// `sdf_add_operand`: see [`crate::sdf::ops`].
    SdfAddOperand(crate::sdf::ops::SdfAddOperand),
    /// `sdf_set_operand_transform`: see [`crate::sdf::ops`].
    SdfSetOperandTransform(crate::sdf::ops::SdfSetOperandTransform),
    /// `sdf_scale_two_hand`: see [`crate::sdf::ops`].
    SdfScaleTwoHand(crate::sdf::ops::SdfScaleTwoHand),
    /// `sdf_cancel_operand`: see [`crate::sdf::ops`].
    SdfCancelOperand(crate::sdf::ops::SdfCancelOperand),
    /// `sdf_copy_operand`: see [`crate::sdf::ops`].
    SdfCopyOperand(crate::sdf::ops::SdfCopyOperand),
    /// `sdf_update`: see [`crate::sdf::ops`].
    SdfUpdate(crate::sdf::ops::SdfUpdate),
    /// `sdf_import_component`: see [`crate::sdf::ops`].
    SdfImportComponent(crate::sdf::ops::SdfImportComponent),
    /// `sdf_set_step`: see [`crate::sdf::ops`].
    SdfSetStep(crate::sdf::ops::SdfSetStep),
    /// Create an empty curve network (styling).
    CurveNetworkCreate(styling::ops::CurveNetworkCreate),
    /// Draw a curve into a network from tracked samples.
    CurveDraw(styling::ops::CurveDraw),
    /// Curve smoother held along a pointer path.
    CurveSmooth(styling::ops::CurveSmooth),
    /// Curve sharpener held along a pointer path.
    CurveSharpen(styling::ops::CurveSharpen),
    /// Curve puller held along a pointer path.
    CurvePull(styling::ops::CurvePull),
    /// Delete a network curve.
    CurveDelete(styling::ops::CurveDelete),
    /// Fill an explicitly picked loop with a patch.
    CurveFillLoop(styling::ops::CurveFillLoop),
    /// Fill every automatically found loop.
    CurveFillAuto(styling::ops::CurveFillAuto),
    /// Surface smoother on a patch.
    SurfaceSmooth(styling::ops::SurfaceEquilibrium),
    /// Surface sharpener on a patch.
    SurfaceSharpen(styling::ops::SurfaceEquilibrium),
    /// Surface puller on a patch.
    SurfacePull(styling::ops::SurfacePull),
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
            Self::SculptCreate(_) => "sculpt_create",
            Self::SculptStroke(_) => "sculpt_stroke",
            Self::SdfCreate(_) => "sdf_create",
            Self::SdfAddOperand(_) => "sdf_add_operand",
            Self::SdfSetOperandTransform(_) => "sdf_set_operand_transform",
            Self::SdfScaleTwoHand(_) => "sdf_scale_two_hand",
            Self::SdfCancelOperand(_) => "sdf_cancel_operand",
            Self::SdfCopyOperand(_) => "sdf_copy_operand",
            Self::SdfUpdate(_) => "sdf_update",
            Self::SdfImportComponent(_) => "sdf_import_component",
            Self::SdfSetStep(_) => "sdf_set_step",
            Self::CurveNetworkCreate(_) => "curve_network_create",
            Self::CurveDraw(_) => "curve_draw",
            Self::CurveSmooth(_) => "curve_smooth",
            Self::CurveSharpen(_) => "curve_sharpen",
            Self::CurvePull(_) => "curve_pull",
            Self::CurveDelete(_) => "curve_delete",
            Self::CurveFillLoop(_) => "curve_fill_loop",
            Self::CurveFillAuto(_) => "curve_fill_auto",
            Self::SurfaceSmooth(_) => "surface_smooth",
            Self::SurfaceSharpen(_) => "surface_sharpen",
            Self::SurfacePull(_) => "surface_pull",
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
            Self::SculptCreate(op) => crate::sculpt::ops::apply_create(doc, op),
            Self::SculptStroke(op) => crate::sculpt::ops::apply_stroke(doc, op),
            Self::SdfCreate(op) => crate::sdf::ops::apply_create(doc, op),
            Self::SdfAddOperand(op) => crate::sdf::ops::apply_add_operand(doc, op),
            Self::SdfSetOperandTransform(op) => {
                crate::sdf::ops::apply_set_operand_transform(doc, op)
            }
            Self::SdfScaleTwoHand(op) => crate::sdf::ops::apply_scale_two_hand(doc, op),
            Self::SdfCancelOperand(op) => crate::sdf::ops::apply_cancel_operand(doc, op),
            Self::SdfCopyOperand(op) => crate::sdf::ops::apply_copy_operand(doc, op),
            Self::SdfUpdate(op) => crate::sdf::ops::apply_update(doc, op),
            Self::SdfImportComponent(op) => crate::sdf::ops::apply_import_component(doc, op),
            Self::SdfSetStep(op) => crate::sdf::ops::apply_set_step(doc, op),
            Self::CurveNetworkCreate(op) => styling::ops::apply_create(doc, op),
            Self::CurveDraw(op) => styling::ops::apply_draw(doc, op),
            Self::CurveSmooth(op) => styling::ops::apply_smooth(doc, op),
            Self::CurveSharpen(op) => styling::ops::apply_sharpen(doc, op),
            Self::CurvePull(op) => styling::ops::apply_pull(doc, op),
            Self::CurveDelete(op) => styling::ops::apply_delete(doc, op),
            Self::CurveFillLoop(op) => styling::ops::apply_fill_loop(doc, op),
            Self::CurveFillAuto(op) => styling::ops::apply_fill_auto(doc, op),
            Self::SurfacePull(op) => styling::ops::apply_surface_pull(doc, op),
            Self::SurfaceSmooth(op) => styling::ops::apply_equilibrium(doc, op, false),
            Self::SurfaceSharpen(op) => styling::ops::apply_equilibrium(doc, op, true),
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
