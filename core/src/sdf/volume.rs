//! [`SdfVolume`]: the document object of paper 2 — a scene SDF built from
//! placed components, with lazily queued operands (§5.4).
//!
//! The object stores its *recipe*: the grid step, imported user meshes,
//! the operands already fused (in order) and the pending ones. The sparse
//! grid, the per-brick mesh pieces and the mesh are derived state, kept
//! beside the recipe (not serialized, not compared, not hashed except
//! through the mesh), rebuilt from the recipe when missing. An update fuses
//! the pending operands into a copy of the previous grid, re-extracts only
//! the bricks whose cells read a changed brick and stitches all pieces in
//! key order; a full extraction stitches freshly extracted pieces in the
//! same order, so the two are equal bit for bit.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::{Arc, OnceLock};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::csg::{brick_count_in_box, fuse, CsgOp};
use super::extract::{assemble, Piece};
use super::features::ExactField;
use super::grid::{BrickKey, SparseGrid, BRICK, BRICK_LEN};
use super::library::{cached_component_sdf, starter_sdf};
use super::placement::{LocalField, PlacedField};
use super::SdfError;
use crate::math::Transform;
use crate::mesh::TriMesh;
use crate::solid::SolidShape;

/// Default grid step (paper §5.4).
pub const DEFAULT_STEP: f64 = 0.01;
/// Allowed grid steps.
pub const STEP_RANGE: [f64; 2] = [0.006, 0.012];
/// The band (clamp) in steps.
pub const BAND_STEPS: f64 = 3.0;
/// Memory budget of a volume's dense bricks.
pub const MEMORY_BUDGET_BYTES: usize = 1 << 30;

/// What an operand is made of.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Component {
    /// An analytic solid, sampled exactly.
    Solid {
        /// The shape and its sizes (local units).
        shape: SolidShape,
    },
    /// A starter-library component (normalized discrete SDF).
    Library {
        /// Its name, one of [`super::library::STARTER_NAMES`].
        name: String,
    },
    /// A component imported into this volume with `sdf_import_component`.
    User {
        /// Its name.
        name: String,
    },
}

/// A closed mesh imported as a user component.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UserMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// A component placed in the volume with a CSG operation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Operand {
    /// What is placed.
    pub component: Component,
    /// How it combines with what came before.
    pub csg: CsgOp,
    /// Placement: local → model space.
    pub transform: Transform,
}

/// Derived state of a volume.
#[derive(Clone, Debug)]
pub struct VolumeState {
    /// The scene grid after the fused operands.
    pub grid: SparseGrid,
    /// Extracted pieces of the bricks with surface.
    pub pieces: BTreeMap<BrickKey, Arc<Piece>>,
    /// The stitched mesh.
    pub mesh: Arc<TriMesh>,
    /// The fused operands' fields, for exact normals at sharp features.
    pub exact: Arc<ExactField>,
}

/// A scene SDF object.
#[derive(Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfVolume {
    /// Grid step in model units (0.006..=0.012).
    pub step: f64,
    /// Imported user components by name.
    #[serde(default)]
    pub user_components: BTreeMap<String, UserMesh>,
    /// Operands fused so far, in order.
    #[serde(default)]
    pub fused: Vec<Operand>,
    /// Operands queued for the next update; still movable.
    #[serde(default)]
    pub pending: Vec<Operand>,
    #[serde(skip)]
    state: OnceLock<Arc<VolumeState>>,
}

impl PartialEq for SdfVolume {
    fn eq(&self, o: &Self) -> bool {
        self.step == o.step
            && self.user_components == o.user_components
            && self.fused == o.fused
            && self.pending == o.pending
    }
}

impl std::fmt::Debug for SdfVolume {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SdfVolume")
            .field("step", &self.step)
            .field("user_components", &self.user_components.len())
            .field("fused", &self.fused)
            .field("pending", &self.pending)
            .finish()
    }
}

/// Checks a grid step.
pub fn check_step(step: f64) -> Result<(), SdfError> {
    if step.is_finite() && (STEP_RANGE[0]..=STEP_RANGE[1]).contains(&step) {
        Ok(())
    } else {
        Err(SdfError::BadStep(step))
    }
}

impl SdfVolume {
    /// An empty volume.
    pub fn new(step: f64) -> Result<Self, SdfError> {
        check_step(step)?;
        Ok(Self {
            step,
            user_components: BTreeMap::new(),
            fused: Vec::new(),
            pending: Vec::new(),
            state: OnceLock::new(),
        })
    }

    /// The local field of a component.
    pub fn local_field(&self, c: &Component) -> Result<LocalField, SdfError> {
        Ok(match c {
            Component::Solid { shape } => {
                shape.validate()?;
                LocalField::Solid(*shape)
            }
            Component::Library { name } => LocalField::Grid(starter_sdf(name)?),
            Component::User { name } => {
                let m = self
                    .user_components
                    .get(name)
                    .ok_or_else(|| SdfError::UnknownComponent(name.clone()))?;
                let mesh = TriMesh::new(m.positions.clone(), m.triangles.clone());
                LocalField::Grid(cached_component_sdf(&mesh)?)
            }
        })
    }

    /// An operand's placed field (validates component and transform).
    pub fn placed(&self, o: &Operand) -> Result<PlacedField, SdfError> {
        let f = PlacedField::new(self.local_field(&o.component)?, &o.transform)?;
        let (lo, hi) = f.world_box;
        let bricks = brick_count_in_box(self.step, lo, hi);
        let budget = (MEMORY_BUDGET_BYTES / (BRICK_LEN * 4)) as f64;
        if bricks.is_nan() || bricks > budget {
            return Err(SdfError::OverBudget {
                needed_mib: (bricks * (BRICK_LEN * 4) as f64 / (1 << 20) as f64) as u64,
                budget_mib: (MEMORY_BUDGET_BYTES >> 20) as u64,
            });
        }
        Ok(f)
    }

    fn band(&self) -> f32 {
        (BAND_STEPS * self.step) as f32
    }

    /// The derived state, rebuilt from the recipe when missing.
    pub fn state(&self) -> Result<Arc<VolumeState>, SdfError> {
        if let Some(s) = self.state.get() {
            return Ok(s.clone());
        }
        let s = Arc::new(self.rebuild()?);
        Ok(self.state.get_or_init(|| s).clone())
    }

    /// Fuses every fused operand from scratch and extracts every brick.
    pub fn rebuild(&self) -> Result<VolumeState, SdfError> {
        let mut grid = SparseGrid::new(self.step, self.band());
        let mut fields = Vec::with_capacity(self.fused.len());
        for o in &self.fused {
            let f = Arc::new(self.placed(o)?);
            fuse(&mut grid, &f, o.csg);
            check_budget(&grid)?;
            fields.push((f, o.csg));
        }
        let exact = Arc::new(ExactField::new(fields, self.band() as f64));
        let pieces = grid.extract_all(Some(&exact));
        let mesh = Arc::new(stitch(&pieces));
        Ok(VolumeState {
            grid,
            pieces,
            mesh,
            exact,
        })
    }

    /// The volume after fusing its pending operands (lazy update, §5.4):
    /// one incremental extraction for the whole queue.
    pub fn updated(&self) -> Result<SdfVolume, SdfError> {
        if self.pending.is_empty() {
            return Err(SdfError::NothingPending);
        }
        let old = self.state()?;
        let mut grid = old.grid.clone();
        let mut changed = BTreeSet::new();
        let mut fields = old.exact.fields().to_vec();
        for o in &self.pending {
            let f = Arc::new(self.placed(o)?);
            changed.extend(fuse(&mut grid, &f, o.csg));
            check_budget(&grid)?;
            // Exact normals at points in the operand's box may now come
            // from it, even where no sample changed: the bricks with
            // surface there are re-extracted. A block with surface reads a
            // stored brick, which lies at most one brick beyond the box, so
            // the stored bricks of the box grown by one brick stand for it
            // (the box's empty bricks cost nothing).
            let (lo, hi) = f.world_box;
            let b = BRICK as f64 * self.step;
            let (klo, khi) = ((lo / b).floor() - 1.0, (hi / b).floor() + 1.0);
            changed.extend(
                grid.bricks
                    .keys()
                    .copied()
                    .filter(|k| (0..3).all(|a| (k[a] as f64) >= klo[a] && (k[a] as f64) <= khi[a])),
            );
            fields.push((f, o.csg));
        }
        let exact = Arc::new(ExactField::new(fields, self.band() as f64));
        let mut dirty = BTreeSet::new();
        for k in &changed {
            for o in super::mc::CORNER_OFFSETS {
                dirty.insert([k[0] - o[0], k[1] - o[1], k[2] - o[2]]);
            }
        }
        let mut pieces = old.pieces.clone();
        let todo: Vec<BrickKey> = dirty
            .into_iter()
            .filter(|k| {
                pieces.remove(k);
                grid.needs_extraction(*k)
            })
            .collect();
        pieces.extend(extract_keys(&grid, &todo, Some(&exact)));
        let mesh = Arc::new(stitch(&pieces));
        let mut next = self.clone();
        next.fused.append(&mut next.pending);
        next.state = OnceLock::new();
        let _ = next.state.set(Arc::new(VolumeState {
            grid,
            pieces,
            mesh,
            exact,
        }));
        Ok(next)
    }

    /// A copy with the recipe changed by `f` and the derived state kept
    /// (for edits that do not touch the fused grid: pending operands).
    pub fn with_pending(&self, f: impl FnOnce(&mut Vec<Operand>)) -> SdfVolume {
        let mut v = self.clone();
        f(&mut v.pending);
        v
    }

    /// A copy with the derived state dropped (it will be rebuilt).
    pub fn without_state(&self) -> SdfVolume {
        let mut v = self.clone();
        v.state = OnceLock::new();
        v
    }

    /// The fused surface: a closed oriented 2-manifold (empty when nothing
    /// is inside).
    pub fn evaluate(&self) -> Result<TriMesh, SdfError> {
        Ok((*self.state()?.mesh).clone())
    }

    /// Preview meshes of the pending operands (their own surfaces, as the
    /// paper draws operands in blue/green/orange before the update).
    pub fn pending_previews(&self) -> Result<Vec<TriMesh>, SdfError> {
        self.pending
            .iter()
            .map(|o| {
                let mut v = SdfVolume::new(self.step)?;
                v.user_components = self.user_components.clone();
                v.fused.push(Operand {
                    csg: CsgOp::Union,
                    ..o.clone()
                });
                v.evaluate()
            })
            .collect()
    }
}

fn check_budget(grid: &SparseGrid) -> Result<(), SdfError> {
    let b = grid.dense_bytes();
    if b > MEMORY_BUDGET_BYTES {
        return Err(SdfError::OverBudget {
            needed_mib: (b >> 20) as u64,
            budget_mib: (MEMORY_BUDGET_BYTES >> 20) as u64,
        });
    }
    Ok(())
}

/// Extracts the bricks `keys` (in parallel, merged in key order); empty
/// pieces are left out.
pub fn extract_keys(
    grid: &SparseGrid,
    keys: &[BrickKey],
    exact: Option<&ExactField>,
) -> BTreeMap<BrickKey, Arc<Piece>> {
    let v: Vec<(BrickKey, Piece)> = keys
        .par_iter()
        .with_min_len(2)
        .map(|k| (*k, grid.extract_brick(*k, exact)))
        .collect();
    v.into_iter()
        .filter(|(_, p)| !p.triangles.is_empty())
        .map(|(k, p)| (k, Arc::new(p)))
        .collect()
}

/// Stitches pieces into the volume's mesh, with the field's gradient as
/// the vertex normals (computed by the owning brick).
pub fn stitch(pieces: &BTreeMap<BrickKey, Arc<Piece>>) -> TriMesh {
    assemble(pieces)
}
