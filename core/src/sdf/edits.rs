//! The `sdf_*` ops' payloads: every user action of paper 2 (§4) as a
//! plain value, and how each changes an [`SdfVolume`] (the document names
//! the volume, in the field `volume`, and applies them to a copy).
//!
//! | op | paper |
//! |---|---|
//! | `sdf_create` | a new scene SDF object |
//! | `sdf_add_operand` | pick a component (menu) and hit it with union / intersect / subtract (§4.2) |
//! | `sdf_set_operand_transform` | grab: translate / rotate / scale an operand (§4.1) |
//! | `sdf_scale_two_hand` | two-hand scaling along X, Y, Z or A, clamped to [0.4, 4] of the scale before the first gesture (§4.3) |
//! | `sdf_cancel_operand` | SceneOperate *cancel*: remove one operand (§4.2) |
//! | `sdf_copy_operand` | copy (§4.4) an operand under a new placement |
//! | `sdf_update` | *update*: fuse the queue, one extraction (§5.4) |
//! | `sdf_import_component` | add a user mesh to the library (§3) |
//! | `sdf_set_step` | the step setting (§5.4) |
//!
//! Copying and deleting whole volumes are the document's `duplicate` and
//! `delete` ops.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::csg::CsgOp;
use super::placement::ScaleAxis;
use super::volume::{check_step, Component, Operand, SdfVolume, UserMesh};
use super::SdfError;
use crate::math::Transform;
use crate::mesh::{validate, TriMesh};

/// The index of a pending operand in its volume's queue. Serialized as a
/// plain number.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
#[serde(transparent)]
pub struct OperandIndex(pub usize);

impl JsonSchema for OperandIndex {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "OperandIndex".into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "type": "integer", "minimum": 0, "x-ref": "operand",
            "description": "A pending CSG operand, by its index in the volume's queue."
        })
    }
}

/// Create an empty SDF volume.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfCreate {
    /// Grid step, 0.004..=0.012 ([`super::volume::DEFAULT_STEP`] is the paper's choice).
    #[schemars(range(min = 0.004, max = 0.012), extend("x-unit" = "m"))]
    pub step: f64,
}

/// Queue a component as the next operand.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfAddOperand {
    /// The component.
    pub component: Component,
    /// How it combines with what came before.
    pub csg: CsgOp,
    /// Its placement.
    #[serde(default)]
    pub transform: Transform,
}

/// Replace a pending operand's placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfSetOperandTransform {
    /// Index among the pending operands.
    pub operand: OperandIndex,
    /// The new placement.
    pub transform: Transform,
}

/// Scale a pending operand by the two-hand ratio of eq. 1 (each scaled
/// axis stays within [0.4, 4] of its scale before the first gesture).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfScaleTwoHand {
    /// Index among the pending operands.
    pub operand: OperandIndex,
    /// Which local axis (or all).
    pub axis: ScaleAxis,
    /// The two hand positions when both grabs began.
    #[schemars(extend("x-unit" = "m"))]
    pub hands_start: [[f64; 3]; 2],
    /// The two hand positions now (when the gesture ended).
    #[schemars(extend("x-unit" = "m"))]
    pub hands_end: [[f64; 3]; 2],
}

/// Remove one pending operand.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfCancelOperand {
    /// Index among the pending operands.
    pub operand: OperandIndex,
}

/// Queue a copy of a pending operand under a new placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfCopyOperand {
    /// Index among the pending operands.
    pub operand: OperandIndex,
    /// The copy's placement.
    pub transform: Transform,
}

/// Fuse every pending operand and extract the surface once.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfUpdate {}

/// Add a closed mesh to the volume's components under `name`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfImportComponent {
    /// The component's name.
    pub name: String,
    /// Vertex positions.
    #[schemars(extend("x-unit" = "m"))]
    pub positions: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// Change the grid step (re-fuses everything at the new step).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfSetStep {
    /// New step, 0.004..=0.012.
    #[schemars(range(min = 0.004, max = 0.012), extend("x-unit" = "m"))]
    pub step: f64,
}

fn check_index(v: &SdfVolume, index: OperandIndex) -> Result<usize, SdfError> {
    if index.0 < v.pending.len() {
        Ok(index.0)
    } else {
        Err(SdfError::BadOperand {
            index: index.0,
            len: v.pending.len(),
        })
    }
}

impl SdfCreate {
    /// The new, empty volume.
    pub fn build(&self) -> Result<SdfVolume, SdfError> {
        SdfVolume::new(self.step)
    }
}

impl SdfAddOperand {
    /// Queues the operand.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        let o = Operand::new(self.component.clone(), self.csg, self.transform);
        v.placed(&o)?;
        *v = v.with_pending(|p| p.push(o));
        Ok(())
    }
}

impl SdfSetOperandTransform {
    /// Moves the operand.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        let i = check_index(v, self.operand)?;
        let mut o = v.pending[i].clone();
        o.transform = self.transform;
        v.placed(&o)?;
        *v = v.with_pending(|p| p[i] = o);
        Ok(())
    }
}

impl SdfScaleTwoHand {
    /// Scales the operand by the two-hand ratio.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        let i = check_index(v, self.operand)?;
        let o = v.pending[i].scaled_two_hand(self.axis, self.hands_start, self.hands_end)?;
        v.placed(&o)?;
        *v = v.with_pending(|p| p[i] = o);
        Ok(())
    }
}

impl SdfCancelOperand {
    /// Removes the operand.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        let i = check_index(v, self.operand)?;
        *v = v.with_pending(|p| {
            p.remove(i);
        });
        Ok(())
    }
}

impl SdfCopyOperand {
    /// Queues the copy.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        let i = check_index(v, self.operand)?;
        let mut o = v.pending[i].clone();
        o.transform = self.transform;
        v.placed(&o)?;
        *v = v.with_pending(|p| p.push(o));
        Ok(())
    }
}

impl SdfUpdate {
    /// Fuses the queue.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        *v = v.updated()?;
        Ok(())
    }
}

impl SdfImportComponent {
    /// Adds the component after checking its mesh.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        if self.name.is_empty() {
            return Err(SdfError::EmptyComponentName);
        }
        if v.user_components.contains_key(&self.name) {
            return Err(SdfError::DuplicateComponent(self.name.clone()));
        }
        let mesh = TriMesh::new(self.positions.clone(), self.triangles.clone());
        let r = validate(&mesh, &Default::default());
        if !r.is_closed_manifold() {
            return Err(SdfError::BadMesh(r.problems()));
        }
        // Computes (and caches) the SDF now, so a bad mesh fails here.
        super::library::cached_component_sdf(&mesh)?;
        v.user_components.insert(
            self.name.clone(),
            UserMesh {
                positions: self.positions.clone(),
                triangles: self.triangles.clone(),
            },
        );
        Ok(())
    }
}

impl SdfSetStep {
    /// Re-fuses at the new step.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        check_step(self.step)?;
        let mut n = v.without_state();
        n.step = self.step;
        n.state()?;
        *v = n;
        Ok(())
    }
}
