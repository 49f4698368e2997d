//! The `sdf_*` ops: every user action of paper 2 (§4) as a log entry.
//!
//! | op | paper |
//! |---|---|
//! | `sdf_create` | a new scene SDF object |
//! | `sdf_add_operand` | pick a component (menu) and hit it with union / intersect / subtract (§4.2) |
//! | `sdf_set_operand_transform` | grab: translate / rotate / scale an operand (§4.1) |
//! | `sdf_scale_two_hand` | two-hand scaling along X, Y, Z or A, ratio clamped to [0.4, 4] (§4.3) |
//! | `sdf_cancel_operand` | SceneOperate *cancel*: remove one operand (§4.2) |
//! | `sdf_copy_operand` | copy (§4.4) an operand under a new placement |
//! | `sdf_update` | *update*: fuse the queue, one extraction (§5.4) |
//! | `sdf_import_component` | add a user mesh to the library (§3) |
//! | `sdf_set_step` | the step setting (§5.4) |
//!
//! Copying and deleting whole volumes are the document's `duplicate` and
//! `delete` ops.

use serde::{Deserialize, Serialize};

use super::csg::CsgOp;
use super::placement::ScaleAxis;
use super::volume::{check_step, Component, Operand, SdfVolume, UserMesh};
use super::SdfError;
use crate::doc::{Document, ObjectId, ObjectKind, OpError, OpOutcome};
use crate::math::Transform;
use crate::mesh::{validate, TriMesh};

/// Create an empty SDF volume.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfCreate {
    /// Grid step, 0.006..=0.012 ([`super::volume::DEFAULT_STEP`] is the paper's choice).
    pub step: f64,
}

/// Queue a component as the next operand.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfAddOperand {
    /// The volume.
    pub volume: ObjectId,
    /// The component.
    pub component: Component,
    /// How it combines with what came before.
    pub csg: CsgOp,
    /// Its placement.
    #[serde(default)]
    pub transform: Transform,
}

/// Replace a pending operand's placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfSetOperandTransform {
    /// The volume.
    pub volume: ObjectId,
    /// Index among the pending operands.
    pub operand: usize,
    /// The new placement.
    pub transform: Transform,
}

/// Scale a pending operand by the two-hand ratio of eq. 1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfScaleTwoHand {
    /// The volume.
    pub volume: ObjectId,
    /// Index among the pending operands.
    pub operand: usize,
    /// Which local axis (or all).
    pub axis: ScaleAxis,
    /// The two hand positions when both grabs began.
    pub hands_start: [[f64; 3]; 2],
    /// The two hand positions now (when the gesture ended).
    pub hands_end: [[f64; 3]; 2],
}

/// Remove one pending operand.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfCancelOperand {
    /// The volume.
    pub volume: ObjectId,
    /// Index among the pending operands.
    pub operand: usize,
}

/// Queue a copy of a pending operand under a new placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfCopyOperand {
    /// The volume.
    pub volume: ObjectId,
    /// Index among the pending operands.
    pub operand: usize,
    /// The copy's placement.
    pub transform: Transform,
}

/// Fuse every pending operand and extract the surface once.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfUpdate {
    /// The volume.
    pub volume: ObjectId,
}

/// Add a closed mesh to the volume's components under `name`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfImportComponent {
    /// The volume.
    pub volume: ObjectId,
    /// The component's name.
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// Change the grid step (re-fuses everything at the new step).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfSetStep {
    /// The volume.
    pub volume: ObjectId,
    /// New step, 0.006..=0.012.
    pub step: f64,
}

fn volume_of(doc: &Document, id: ObjectId, op: &'static str) -> Result<SdfVolume, OpError> {
    match &doc.get(id)?.kind {
        ObjectKind::SdfVolume(v) => Ok(v.clone()),
        #[allow(unreachable_patterns)]
        other => Err(OpError::WrongKind {
            id,
            op,
            expected: "sdf_volume",
            found: other.name(),
        }),
    }
}

fn check_index(v: &SdfVolume, index: usize) -> Result<(), SdfError> {
    if index < v.pending.len() {
        Ok(())
    } else {
        Err(SdfError::BadOperand {
            index,
            len: v.pending.len(),
        })
    }
}

fn put(doc: &mut Document, id: ObjectId, v: SdfVolume) -> Result<OpOutcome, OpError> {
    doc.replace(id, ObjectKind::SdfVolume(v))?;
    Ok(OpOutcome::default())
}

/// Applies `sdf_create`.
pub fn apply_create(doc: &mut Document, op: &SdfCreate) -> Result<OpOutcome, OpError> {
    let v = SdfVolume::new(op.step)?;
    let id = doc.insert(ObjectKind::SdfVolume(v))?;
    Ok(OpOutcome { created: Some(id) })
}

/// Applies `sdf_add_operand`.
pub fn apply_add_operand(doc: &mut Document, op: &SdfAddOperand) -> Result<OpOutcome, OpError> {
    let v = volume_of(doc, op.volume, "sdf_add_operand")?;
    let o = Operand::new(op.component.clone(), op.csg, op.transform);
    v.placed(&o)?;
    put(doc, op.volume, v.with_pending(|p| p.push(o)))
}

/// Applies `sdf_set_operand_transform`.
pub fn apply_set_operand_transform(
    doc: &mut Document,
    op: &SdfSetOperandTransform,
) -> Result<OpOutcome, OpError> {
    let v = volume_of(doc, op.volume, "sdf_set_operand_transform")?;
    check_index(&v, op.operand)?;
    let mut o = v.pending[op.operand].clone();
    o.transform = op.transform;
    v.placed(&o)?;
    put(doc, op.volume, v.with_pending(|p| p[op.operand] = o))
}

/// Applies `sdf_scale_two_hand`.
pub fn apply_scale_two_hand(
    doc: &mut Document,
    op: &SdfScaleTwoHand,
) -> Result<OpOutcome, OpError> {
    let v = volume_of(doc, op.volume, "sdf_scale_two_hand")?;
    check_index(&v, op.operand)?;
    let o = v.pending[op.operand].scaled_two_hand(op.axis, op.hands_start, op.hands_end)?;
    v.placed(&o)?;
    put(doc, op.volume, v.with_pending(|p| p[op.operand] = o))
}

/// Applies `sdf_cancel_operand`.
pub fn apply_cancel_operand(
    doc: &mut Document,
    op: &SdfCancelOperand,
) -> Result<OpOutcome, OpError> {
    let v = volume_of(doc, op.volume, "sdf_cancel_operand")?;
    check_index(&v, op.operand)?;
    put(
        doc,
        op.volume,
        v.with_pending(|p| {
            p.remove(op.operand);
        }),
    )
}

/// Applies `sdf_copy_operand`.
pub fn apply_copy_operand(doc: &mut Document, op: &SdfCopyOperand) -> Result<OpOutcome, OpError> {
    let v = volume_of(doc, op.volume, "sdf_copy_operand")?;
    check_index(&v, op.operand)?;
    let mut o = v.pending[op.operand].clone();
    o.transform = op.transform;
    v.placed(&o)?;
    put(doc, op.volume, v.with_pending(|p| p.push(o)))
}

/// Applies `sdf_update`.
pub fn apply_update(doc: &mut Document, op: &SdfUpdate) -> Result<OpOutcome, OpError> {
    let v = volume_of(doc, op.volume, "sdf_update")?;
    put(doc, op.volume, v.updated()?)
}

/// Applies `sdf_import_component`.
pub fn apply_import_component(
    doc: &mut Document,
    op: &SdfImportComponent,
) -> Result<OpOutcome, OpError> {
    let mut v = volume_of(doc, op.volume, "sdf_import_component")?;
    if op.name.is_empty() {
        return Err(SdfError::BadMesh("the component name is empty".into()).into());
    }
    if v.user_components.contains_key(&op.name) {
        return Err(SdfError::DuplicateComponent(op.name.clone()).into());
    }
    let mesh = TriMesh::new(op.positions.clone(), op.triangles.clone());
    let r = validate(&mesh, &Default::default());
    if !r.is_closed_manifold() {
        return Err(SdfError::BadMesh(r.problems()).into());
    }
    // Computes (and caches) the SDF now, so a bad mesh fails here.
    super::library::cached_component_sdf(&mesh)?;
    v.user_components.insert(
        op.name.clone(),
        UserMesh {
            positions: op.positions.clone(),
            triangles: op.triangles.clone(),
        },
    );
    put(doc, op.volume, v)
}

/// Applies `sdf_set_step`.
pub fn apply_set_step(doc: &mut Document, op: &SdfSetStep) -> Result<OpOutcome, OpError> {
    let v = volume_of(doc, op.volume, "sdf_set_step")?;
    check_step(op.step)?;
    let mut n = v.without_state();
    n.step = op.step;
    n.state()?;
    put(doc, op.volume, n)
}
