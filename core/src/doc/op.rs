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
