//! `add_solid` and `edit_solid`: parametric solids.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{Apply, EditCx, ObjectEdit, OpOutcome};
use crate::doc::{Document, ObjectKind, OpError, Solid};
use crate::math::Transform;
use crate::solid::{SolidShape, DEFAULT_SEGMENTS};

fn default_segments() -> u32 {
    DEFAULT_SEGMENTS
}

/// Create a parametric solid.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AddSolid {
    /// Shape and sizes.
    pub shape: SolidShape,
    /// Segments around each circle.
    #[serde(default = "default_segments")]
    #[schemars(range(min = 8, max = 1024))]
    pub segments: u32,
    /// Placement.
    #[serde(default)]
    pub transform: Transform,
}

impl Apply for AddSolid {
    const KIND: &'static str = "solid";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        let id = doc.insert(ObjectKind::Solid(Solid {
            shape: self.shape,
            segments: self.segments,
            transform: self.transform,
        }))?;
        Ok(OpOutcome { created: Some(id) })
    }
}

/// Change a solid's shape (and resolution), keeping its placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EditSolid {
    /// New shape and sizes.
    pub shape: SolidShape,
    /// New segments around each circle.
    #[serde(default = "default_segments")]
    #[schemars(range(min = 8, max = 1024))]
    pub segments: u32,
}

impl ObjectEdit for EditSolid {
    type Target = Solid;
    fn apply(&self, solid: &mut Solid, _: &mut EditCx<'_>) -> Result<(), OpError> {
        solid.shape = self.shape;
        solid.segments = self.segments;
        Ok(())
    }
}
