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
//! | `sdf_move_fused` | move the fused result `M` (Fig. 2: `M` shrunk to `D`) |
//! | `sdf_copy_fused` | copy (§4.4) the fused result as a new operand: the result used as a component |
//! | `sdf_component_from_object` | "users are allowed to freely augment the dataset" (§3): any document object as a component |
//!
//! Copying and deleting whole volumes are the document's `duplicate` and
//! `delete` ops.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::cache::SdfCache;
use super::csg::CsgOp;
use super::placement::ScaleAxis;
use super::volume::{check_step, default_cache, Component, Operand, SdfVolume, UserMesh};
use super::SdfError;
use crate::id::{index_type, ObjectId};
use crate::math::{DAffine3, DVec3, Transform};
use crate::mesh::{validate, TriMesh};

index_type!(
    /// The index of a pending operand in its volume's queue. Serialized as a
    /// plain number.
    OperandIndex,
    "operand",
    "A pending CSG operand, by its index in the volume's queue."
);

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

/// Move the fused result: every fused operand placed at `transform ∘ Tᵢ`
/// and the grid rebuilt (pending operands stay where they are).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfMoveFused {
    /// The motion, in the volume's own frame: a similarity (rotation,
    /// translation, one scale for all three axes); a per-axis scale is
    /// refused (copy the result with `sdf_copy_fused` and scale the copy).
    pub transform: Transform,
}

/// Copy the fused result: its surface becomes user component `name` of the
/// volume and is queued as a new operand at `transform ∘ (where the result
/// is)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfCopyFused {
    /// The new component's name (not empty, not already a component).
    #[schemars(length(min = 1, max = 256))]
    pub name: String,
    /// How the copy combines with what came before.
    pub csg: CsgOp,
    /// Where the copy goes, relative to the result (identity: on it).
    #[serde(default)]
    pub transform: Transform,
}

/// Make a component from any closed object of the document (its mesh as
/// the document has it, taken into the volume's own frame), optionally
/// queued as an operand exactly where the object is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SdfComponentFromObject {
    /// The object whose mesh becomes the component (any kind; its mesh
    /// must be a closed oriented 2-manifold).
    pub object: ObjectId,
    /// The component's name (not empty, not already a component).
    #[schemars(length(min = 1, max = 256))]
    pub name: String,
    /// If given, the component is also queued as an operand, combined this
    /// way, placed where the object is.
    #[serde(default)]
    pub csg: Option<CsgOp>,
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

/// Pending operand `index` with its transform set to `transform`, checked
/// to fit the volume (what a move and a copy of an operand share), and
/// its position in the queue.
fn re_placed(
    v: &SdfVolume,
    index: OperandIndex,
    transform: Transform,
) -> Result<(usize, Operand), SdfError> {
    let i = check_index(v, index)?;
    let mut o = v.pending[i].clone();
    o.transform = transform;
    v.placed(&o)?;
    v.check_placed_reuse(Some(&v.pending[i].transform), &o, default_cache())?;
    Ok((i, o))
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
        v.check_placed_reuse(None, &o, default_cache())?;
        *v = v.with_pending(|p| p.push(o));
        Ok(())
    }
}

impl SdfSetOperandTransform {
    /// Moves the operand.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        let (i, o) = re_placed(v, self.operand, self.transform)?;
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
        v.check_placed_reuse(Some(&v.pending[i].transform), &o, default_cache())?;
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
        let (_, o) = re_placed(v, self.operand, self.transform)?;
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
        v.user_components
            .insert(self.name.clone(), UserMesh::from_mesh(mesh, None));
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

impl SdfMoveFused {
    /// Moves the fused result.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        *v = v.with_fused_moved(&self.transform, default_cache())?;
        Ok(())
    }
}

impl SdfCopyFused {
    /// Queues the copy of the fused result.
    pub fn apply_to(&self, v: &mut SdfVolume) -> Result<(), SdfError> {
        if self.name.is_empty() {
            return Err(SdfError::EmptyComponentName);
        }
        *v = v.with_fused_copy(&self.name, &self.transform, self.csg, default_cache())?;
        Ok(())
    }
}

impl SdfComponentFromObject {
    /// Adds `mesh` (the object's model-space mesh) as a component of `v`,
    /// whose placement is `placement` (its own frame to model space).
    /// `source_step`: the object's own grid step when it is an SDF volume
    /// (the component keeps the finer of it and `v`'s, see
    /// [`super::reuse`]).
    pub fn apply_to(
        &self,
        v: &mut SdfVolume,
        mesh: &TriMesh,
        placement: &DAffine3,
        source_step: Option<f64>,
    ) -> Result<(), SdfError> {
        self.apply_with(v, mesh, placement, source_step, default_cache())
    }

    /// [`Self::apply_to`] with an explicit cache.
    pub fn apply_with(
        &self,
        v: &mut SdfVolume,
        mesh: &TriMesh,
        placement: &DAffine3,
        source_step: Option<f64>,
        cache: &SdfCache,
    ) -> Result<(), SdfError> {
        if self.name.is_empty() {
            return Err(SdfError::EmptyComponentName);
        }
        if v.user_components.contains_key(&self.name) {
            return Err(SdfError::DuplicateComponent(self.name.clone()));
        }
        if mesh.triangles.is_empty() {
            return Err(SdfError::EmptyResult);
        }
        let (local, scale) = if *placement == DAffine3::IDENTITY {
            (mesh.clone(), 1.0)
        } else {
            let inv = placement.inverse();
            if !inv.to_cols_array().iter().all(|x| x.is_finite()) {
                return Err(SdfError::BadMesh(
                    "the volume's placement cannot be inverted".into(),
                ));
            }
            let mut m = TriMesh::new(
                mesh.positions
                    .iter()
                    .map(|p| inv.transform_point3(DVec3::from_array(*p)).to_array())
                    .collect(),
                mesh.triangles.clone(),
            );
            if inv.matrix3.determinant() < 0.0 {
                for t in &mut m.triangles {
                    t.swap(1, 2);
                }
            }
            // Model units per unit of the volume's frame (the smallest
            // axis scale: the frame's finest direction).
            let s = [inv.matrix3.x_axis, inv.matrix3.y_axis, inv.matrix3.z_axis]
                .iter()
                .map(|c| 1.0 / c.length())
                .fold(f64::INFINITY, f64::min);
            (m, s)
        };
        // Steps are in model units; the mesh is in the volume's frame.
        let what = format!("object #{}", self.object.0);
        let step = super::reuse::reuse_step(source_step, v.step) / scale;
        // The component's budget first (and its mesh checked closed), then
        // its walls.
        let (user, back) = super::reuse::component_from_mesh(&local, Some(step), cache)?;
        super::reuse::check_walls(&local, v.step, scale, &what)?;
        let want = super::reuse::shape(&local);
        let mut n = v.clone();
        n.user_components.insert(self.name.clone(), user);
        let o = Operand::new(
            Component::User {
                name: self.name.clone(),
            },
            self.csg.unwrap_or(CsgOp::Union),
            back,
        );
        n.placed_with(&o, cache)?;
        if let Some(want) = want {
            // Topology here; walls below two cells were refused above
            // (`check_walls`). The volume is not compared: what an object
            // with thick walls loses is the grid's own chords (a 3 cm
            // sphere at 1 cm keeps 93.7%).
            n.check_reuse(&o, want, None, &what, cache)?;
        }
        if self.csg.is_some() {
            n = n.with_pending(|p| p.push(o));
        }
        *v = n;
        Ok(())
    }
}
