//! Ops on any object: placement (`set_transform`, `transform_by`),
//! `duplicate`, `delete`, `rename_object` and `reserve_ids`. One op family for every
//! kind; see [`crate::doc::Object`] for how each kind is placed.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{Apply, OpOutcome};
use crate::doc::{Document, ObjectId, OpError};
use crate::math::{DQuat, DVec3, Transform};

/// Longest name an object may have, in bytes.
pub const MAX_NAME_LEN: usize = 256;

/// Replace an object's placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SetTransform {
    /// The object.
    pub id: ObjectId,
    /// New placement.
    pub transform: Transform,
}

impl Apply for SetTransform {
    const KIND: &'static str = "document";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        self.transform.validate()?;
        doc.set_placement(self.id, self.transform)?;
        Ok(OpOutcome::default())
    }
}

/// Apply `transform` after the object's current placement (in model space).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TransformBy {
    /// The object.
    pub id: ObjectId,
    /// The increment. A non-uniform scale is allowed only while the object
    /// is unrotated (otherwise the result would shear).
    pub transform: Transform,
}

impl Apply for TransformBy {
    const KIND: &'static str = "document";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        let current = doc.get(self.id)?.transform();
        doc.set_placement(self.id, compose(&self.transform, &current)?)?;
        Ok(OpOutcome::default())
    }
}

/// Copy an object (kind, placement and name); the copy gets the next id.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Duplicate {
    /// The object to copy.
    pub id: ObjectId,
}

impl Apply for Duplicate {
    const KIND: &'static str = "document";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        let id = doc.duplicate(self.id)?;
        Ok(OpOutcome { created: Some(id) })
    }
}

/// Delete an object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Delete {
    /// The object.
    pub id: ObjectId,
}

impl Apply for Delete {
    const KIND: &'static str = "document";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        doc.remove(self.id)?;
        Ok(OpOutcome::default())
    }
}

/// Give an object a name.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RenameObject {
    /// The object.
    pub id: ObjectId,
    /// The new name (`""` clears it). At most 256 bytes, no control
    /// characters.
    #[schemars(length(max = 256))]
    pub name: String,
}

impl Apply for RenameObject {
    const KIND: &'static str = "document";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        if self.name.len() > MAX_NAME_LEN || self.name.chars().any(char::is_control) {
            return Err(OpError::BadName {
                name: self.name.chars().take(40).collect(),
                max: MAX_NAME_LEN,
            });
        }
        doc.rename(self.id, &self.name)?;
        Ok(OpOutcome::default())
    }
}

/// Make the next created objects take ids from `first` on. Written by a
/// shared session before each person's op that creates objects, so each
/// person creates in their own id range (`crate::doc::shared`): two people
/// creating at once never get the same id, and an op keeps the ids it
/// created when it is rebased onto someone else's. Nobody types it; it is
/// in the saved history so that a replay gives every object its id again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReserveIds {
    /// The id the next created object takes.
    #[schemars(range(min = 1, max = 4294967294u32))]
    pub first: u32,
}

impl Apply for ReserveIds {
    const KIND: &'static str = "session";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        doc.reserve_ids(self.first)?;
        Ok(OpOutcome::default())
    }
}

/// `outer` after `inner`, as one scale-rotate-translate transform.
pub(crate) fn compose(outer: &Transform, inner: &Transform) -> Result<Transform, OpError> {
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
