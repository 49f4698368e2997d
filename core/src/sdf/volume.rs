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
//!
//! **Resampled operands are cached** ([`super::sample`]): each operand's
//! field on the lattice is kept, per component, placement and step, in a
//! small cache shared by a volume and the volumes derived from it (an
//! update, a moved or added operand). An update resamples only the
//! operands placed differently since they were last sampled: during a
//! drag (the host calling [`SdfVolume::updated`] on the volume with the
//! dragged operand moved), the dragged one. Entries are a pure function of
//! their key, so hits and misses give the same bits.
//!
//! **Component SDFs** come from an [`SdfCache`] the caller passes in (the
//! host owns it, with or without a persistent store); the methods without
//! a cache argument use [`default_cache`], the process's memory-only
//! cache, for callers that do not hold one yet.
//!
//! **Memory** (measured on the paper's chair, `scripts/bench/sdf.py`):
//! a dense brick is 2 KiB, and the bricks near the surface grow as
//! `1/step²`: see the module doc of [`super`] for the numbers per step.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::{Arc, Mutex, OnceLock};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::budget::{surface_bricks, Work, BRICK_BYTES};
use super::cache::SdfCache;
use super::csg::{brick_count_in_box, fuse_sampled, CsgOp};
use super::extract::{assemble, Piece};
use super::features::ExactField;
use super::fold::FoldCell;
use super::grid::{BrickKey, SparseGrid, BRICK, BRICK_LEN};
use super::placement::{two_hand_scale, LocalField, PlacedField, ScaleAxis};
use super::sample::{sample_operand, SampledOperand};
use super::SdfError;
use crate::math::Transform;
use crate::mesh::TriMesh;
use crate::solid::SolidShape;

/// Default grid step (paper §5.4).
pub const DEFAULT_STEP: f64 = 0.01;
/// Allowed grid steps (the paper tried 0.006 to 0.012 on a GPU; 0.004
/// keeps a 0.03 handle's tube 7 samples across).
pub const STEP_RANGE: [f64; 2] = [0.004, 0.012];
/// The band (clamp) in steps.
pub const BAND_STEPS: f64 = 3.0;
pub use super::budget::MEMORY_BUDGET_BYTES;
/// The share of a surface brick's time (sampling, folding, extracting)
/// that is the operand's evaluation: 0.32 to 0.39 measured on chains of
/// copies of the fused result (their folds cost 3.4 to 6.4 plain samples
/// each); at 0.5 the estimate of the longest accepted copy was 6.4 s for
/// 6.1 s measured, so a margin.
const FOLD_SAMPLING_SHARE: f64 = 0.75;
/// Resampled operands kept per volume lineage.
const SAMPLE_CACHE_ENTRIES: usize = 32;

/// What an operand is made of.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Component {
    /// An analytic solid, sampled exactly.
    Solid {
        /// The shape and its sizes (local units).
        shape: SolidShape,
    },
    /// A library component (normalized discrete SDF).
    Library {
        /// Its name, one of [`super::library::catalog`]'s.
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
    /// The step of the component's SDF in the units of `positions`, for
    /// objects and results reused at their own resolution
    /// ([`super::reuse`]); `None`: the library's normalized grid (40 cells
    /// across, §5.2), as for imported files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    /// For a copy of the fused result ([`super::reuse`]): the operands it
    /// was fused from, in the volume's frame. Its field is their fold
    /// (exact), and the mesh (the result's surface) is drawn and budgeted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fused: Option<Vec<Operand>>,
    /// The fold, once built (shared by the clones of this component).
    #[serde(skip)]
    pub(super) fold: FoldCell,
}

impl UserMesh {
    /// A component made from a closed mesh whose SDF is sampled with one
    /// cell `step` in its units (`None`: the library's grid).
    pub fn from_mesh(mesh: TriMesh, step: Option<f64>) -> Self {
        Self {
            positions: mesh.positions,
            triangles: mesh.triangles,
            step,
            fused: None,
            fold: FoldCell::default(),
        }
    }

    /// A copy of a fused result: its surface `mesh` and the `operands` it
    /// was fused from.
    pub fn from_fused(mesh: TriMesh, operands: Vec<Operand>) -> Self {
        Self {
            fused: Some(operands),
            ..Self::from_mesh(mesh, None)
        }
    }

    /// The mesh.
    pub fn mesh(&self) -> TriMesh {
        TriMesh::new(self.positions.clone(), self.triangles.clone())
    }
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
    /// The scale the operand had before its first two-hand scale: later
    /// two-hand gestures stay within [`super::placement::TWO_HAND_RATIO`]
    /// of it (paper §4.3), however many there are.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale_reference: Option<[f64; 3]>,
}

impl Operand {
    /// An operand with no two-hand scale so far.
    pub fn new(component: Component, csg: CsgOp, transform: Transform) -> Self {
        Self {
            component,
            csg,
            transform,
            scale_reference: None,
        }
    }

    /// The operand after a two-hand scale gesture (§4.3, eq. 1) on `axis`:
    /// the first gesture records the scale it started from, and every
    /// gesture keeps each axis within [0.4, 4] of that reference.
    pub fn scaled_two_hand(
        &self,
        axis: ScaleAxis,
        hands_start: [[f64; 3]; 2],
        hands_end: [[f64; 3]; 2],
    ) -> Result<Operand, SdfError> {
        let reference = self.scale_reference.unwrap_or(self.transform.scale);
        let mut o = self.clone();
        o.transform.scale = two_hand_scale(
            self.transform.scale,
            reference,
            axis,
            hands_start,
            hands_end,
        )?;
        o.scale_reference = Some(reference);
        o.transform.validate()?;
        Ok(o)
    }
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

/// What identifies a resampled operand: its local field, its placement
/// (exact bits) and the lattice step.
#[derive(Clone, Debug, PartialEq)]
struct SampleKey {
    field: FieldId,
    transform: [u64; 10],
    step: u64,
}

#[derive(Clone, Debug, PartialEq)]
enum FieldId {
    Solid(SolidShape),
    /// The address of the shared grid (kept alive by the entry).
    Grid(usize),
    /// The address of the shared fold (kept alive by the entry).
    Fold(usize),
}

struct SampleEntry {
    key: SampleKey,
    field: Arc<PlacedField>,
    sampled: Arc<SampledOperand>,
    preview: OnceLock<Arc<TriMesh>>,
}

/// Resampled operands, most recently used last.
#[derive(Default)]
struct SampleCache {
    entries: Vec<Arc<SampleEntry>>,
}

/// A scene SDF object.
#[derive(Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfVolume {
    /// Grid step in model units ([`STEP_RANGE`]).
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
    #[serde(skip)]
    samples: Arc<Mutex<SampleCache>>,
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

static DEFAULT_CACHE: OnceLock<SdfCache> = OnceLock::new();

/// The process's component cache, for callers that do not pass one (the
/// document's ops, until the document carries the host's cache): the one
/// given to [`set_default_cache`], else a memory-only cache.
pub fn default_cache() -> &'static SdfCache {
    DEFAULT_CACHE.get_or_init(SdfCache::new)
}

/// Makes `cache` (a host's, usually with a persistent store) the
/// [`default_cache`]. Only the first call before any use counts: returns
/// `false` (and changes nothing) if the default was already set or used.
pub fn set_default_cache(cache: SdfCache) -> bool {
    DEFAULT_CACHE.set(cache).is_ok()
}

fn transform_bits(t: &Transform) -> [u64; 10] {
    let mut b = [0u64; 10];
    let all = t.translate.iter().chain(&t.rotate).chain(&t.scale);
    for (o, x) in b.iter_mut().zip(all) {
        *o = x.to_bits();
    }
    b
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
            samples: Arc::default(),
        })
    }

    /// The local field of a component, its SDF from `cache`.
    pub fn local_field_with(
        &self,
        c: &Component,
        cache: &SdfCache,
    ) -> Result<LocalField, SdfError> {
        Ok(match c {
            Component::Solid { shape } => {
                shape.validate()?;
                LocalField::Solid(*shape)
            }
            Component::Library { name } => LocalField::Grid(cache.library_field(name)?),
            Component::User { name } => {
                let m = self
                    .user_components
                    .get(name)
                    .ok_or_else(|| SdfError::UnknownComponent(name.clone()))?;
                match &m.fused {
                    Some(operands) => LocalField::Fold(self.fold_of(m, operands, cache)?),
                    None => LocalField::Grid(cache.component_field_at(&m.mesh(), m.step)?),
                }
            }
        })
    }

    /// [`Self::local_field_with`] the [`default_cache`].
    pub fn local_field(&self, c: &Component) -> Result<LocalField, SdfError> {
        self.local_field_with(c, default_cache())
    }

    /// An operand's placed field (validates component and transform, and
    /// that its box fits the memory budget).
    pub fn placed_with(&self, o: &Operand, cache: &SdfCache) -> Result<PlacedField, SdfError> {
        let f = self.placed_unchecked(o, cache)?;
        self.operand_work(&f).check("fusing this operand")?;
        Ok(f)
    }

    /// [`Self::placed_with`] but for its time: for an op that checks the
    /// operand's work as part of its own.
    pub(crate) fn placed_unchecked(
        &self,
        o: &Operand,
        cache: &SdfCache,
    ) -> Result<PlacedField, SdfError> {
        let f = PlacedField::new(self.local_field_with(&o.component, cache)?, &o.transform)?;
        let (lo, hi) = f.world_box;
        let bricks = brick_count_in_box(self.step, lo, hi);
        let budget = (MEMORY_BUDGET_BYTES / (BRICK_LEN * 4)) as f64;
        if bricks.is_nan() || bricks > budget {
            return Err(SdfError::OverBudget(super::budget::grid_memory(
                super::budget::mib_ceil(bricks * BRICK_BYTES),
                (MEMORY_BUDGET_BYTES >> 20) as u64,
            )));
        }
        Ok(f)
    }

    /// The work of resampling, fusing and extracting a placed operand
    /// (counted, not done: [`super::budget`]).
    pub fn operand_work(&self, f: &PlacedField) -> Work {
        let (lo, hi) = f.world_box;
        let near = surface_bricks(f.surface_area(), self.step);
        // A fold's sample costs `cost` plain ones (its far test as much);
        // the sampling is a share of a surface brick's time.
        let (far, dense) = match &f.field {
            LocalField::Fold(x) => (x.cost, 1.0 + FOLD_SAMPLING_SHARE * (x.cost - 1.0)),
            _ => (1.0, 1.0),
        };
        Work {
            region_bricks: brick_count_in_box(self.step, lo, hi) * far,
            surface_bricks: near * dense,
            held_bricks: near,
            ..Work::default()
        }
    }

    /// Dense bricks the volume's grid holds now (0 when it was not built).
    pub(crate) fn held_bricks(&self) -> f64 {
        self.state
            .get()
            .map_or(0.0, |s| s.grid.dense_bytes() as f64 / BRICK_BYTES)
    }

    /// The work of fusing `operands` into this volume's grid (as now, or
    /// from scratch with `fresh`), checked against the budgets before any
    /// of it is done. `what` names it in the refusal.
    pub fn check_fusion(
        &self,
        operands: &[Operand],
        fresh: bool,
        what: &str,
        cache: &SdfCache,
    ) -> Result<(), SdfError> {
        let mut w = Work {
            held_bricks: if fresh { 0.0 } else { self.held_bricks() },
            ..Work::default()
        };
        for o in operands {
            let f = self.placed_with(o, cache)?;
            w = w.plus(&self.operand_work(&f));
        }
        w.check(what)
    }

    /// [`Self::placed_with`] the [`default_cache`].
    pub fn placed(&self, o: &Operand) -> Result<PlacedField, SdfError> {
        self.placed_with(o, default_cache())
    }

    fn band(&self) -> f32 {
        (BAND_STEPS * self.step) as f32
    }

    /// The operand resampled onto this volume's lattice, from the sample
    /// cache or resampled now (and kept).
    fn sample_entry(&self, o: &Operand, cache: &SdfCache) -> Result<Arc<SampleEntry>, SdfError> {
        let field = self.placed_with(o, cache)?;
        let key = SampleKey {
            field: match &field.field {
                LocalField::Solid(s) => FieldId::Solid(*s),
                LocalField::Grid(g) => FieldId::Grid(Arc::as_ptr(g) as usize),
                LocalField::Fold(x) => FieldId::Fold(Arc::as_ptr(x) as usize),
            },
            transform: transform_bits(&o.transform),
            step: self.step.to_bits(),
        };
        if let Ok(mut c) = self.samples.lock() {
            if let Some(i) = c.entries.iter().position(|e| e.key == key) {
                let e = c.entries.remove(i);
                c.entries.push(e.clone());
                return Ok(e);
            }
        }
        let sampled = Arc::new(sample_operand(&field, self.step, self.band()));
        let e = Arc::new(SampleEntry {
            key,
            field: Arc::new(field),
            sampled,
            preview: OnceLock::new(),
        });
        if let Ok(mut c) = self.samples.lock() {
            if c.entries.len() >= SAMPLE_CACHE_ENTRIES {
                c.entries.remove(0);
            }
            c.entries.push(e.clone());
        }
        Ok(e)
    }

    /// The operand's placed field and its values on this volume's lattice
    /// (resampled only when not cached).
    pub fn sampled_with(
        &self,
        o: &Operand,
        cache: &SdfCache,
    ) -> Result<(Arc<PlacedField>, Arc<SampledOperand>), SdfError> {
        let e = self.sample_entry(o, cache)?;
        Ok((e.field.clone(), e.sampled.clone()))
    }

    /// Resampled operands held for this volume and the volumes derived
    /// from it.
    pub fn cached_samples(&self) -> usize {
        self.samples.lock().map_or(0, |c| c.entries.len())
    }

    /// The derived state, rebuilt from the recipe when missing.
    pub fn state_with(&self, cache: &SdfCache) -> Result<Arc<VolumeState>, SdfError> {
        if let Some(s) = self.state.get() {
            return Ok(s.clone());
        }
        let s = Arc::new(self.rebuild_with(cache)?);
        Ok(self.state.get_or_init(|| s).clone())
    }

    /// [`Self::state_with`] the [`default_cache`].
    pub fn state(&self) -> Result<Arc<VolumeState>, SdfError> {
        self.state_with(default_cache())
    }

    /// Fuses every fused operand from scratch and extracts every brick.
    pub fn rebuild_with(&self, cache: &SdfCache) -> Result<VolumeState, SdfError> {
        self.check_fusion(&self.fused, true, "rebuilding the volume", cache)?;
        let mut grid = SparseGrid::new(self.step, self.band());
        let mut fields = Vec::with_capacity(self.fused.len());
        for o in &self.fused {
            let e = self.sample_entry(o, cache)?;
            fuse_sampled(&mut grid, &e.sampled, o.csg);
            check_budget(&grid)?;
            fields.push((e.field.clone(), o.csg));
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

    /// [`Self::rebuild_with`] the [`default_cache`].
    pub fn rebuild(&self) -> Result<VolumeState, SdfError> {
        self.rebuild_with(default_cache())
    }

    /// The volume after fusing its pending operands (lazy update, §5.4):
    /// one incremental extraction for the whole queue.
    pub fn updated_with(&self, cache: &SdfCache) -> Result<SdfVolume, SdfError> {
        if self.pending.is_empty() {
            return Err(SdfError::NothingPending);
        }
        let old = self.state_with(cache)?;
        self.check_fusion(&self.pending, false, "this update", cache)?;
        let entries = self
            .pending
            .iter()
            .map(|o| self.sample_entry(o, cache))
            .collect::<Result<Vec<_>, _>>()?;
        let mut grid = old.grid.clone();
        // Nothing fused yet (the first update, or every operand queued
        // again): every stored brick is new, so the incremental bookkeeping
        // below would mark the whole grid dirty brick by brick and extract
        // it through map lookups. One full extraction gives the same pieces
        // (a piece depends on its block and the exact field alone).
        let cold = old.grid.bricks.is_empty();
        let mut changed = BTreeSet::new();
        let mut fields = old.exact.fields().to_vec();
        for (o, e) in self.pending.iter().zip(&entries) {
            let fused = fuse_sampled(&mut grid, &e.sampled, o.csg);
            check_budget(&grid)?;
            fields.push((e.field.clone(), o.csg));
            if cold {
                continue;
            }
            changed.extend(fused);
            // Exact normals at points in the operand's box may now come
            // from it, even where no sample changed: the bricks with
            // surface there are re-extracted. A block with surface reads a
            // stored brick, which lies at most one brick beyond the box, so
            // the stored bricks of the box grown by one brick stand for it
            // (the box's empty bricks cost nothing).
            let (lo, hi) = e.field.world_box;
            let b = BRICK as f64 * self.step;
            let (klo, khi) = ((lo / b).floor() - 1.0, (hi / b).floor() + 1.0);
            changed.extend(stored_in_box(&grid, klo.to_array(), khi.to_array()));
        }
        let exact = Arc::new(ExactField::new(fields, self.band() as f64));
        let pieces = if cold {
            grid.extract_all(Some(&exact))
        } else {
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
            pieces
        };
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

    /// [`Self::updated_with`] the [`default_cache`].
    pub fn updated(&self) -> Result<SdfVolume, SdfError> {
        self.updated_with(default_cache())
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
    pub fn evaluate_with(&self, cache: &SdfCache) -> Result<TriMesh, SdfError> {
        Ok((*self.state_with(cache)?.mesh).clone())
    }

    /// [`Self::evaluate_with`] the [`default_cache`].
    pub fn evaluate(&self) -> Result<TriMesh, SdfError> {
        self.evaluate_with(default_cache())
    }

    /// Preview meshes of the pending operands (their own surfaces, as the
    /// paper draws operands in blue/green/orange before the update), from
    /// their cached samples; each is kept with its sample.
    pub fn pending_previews_with(&self, cache: &SdfCache) -> Result<Vec<Arc<TriMesh>>, SdfError> {
        self.pending
            .iter()
            .map(|o| {
                let e = self.sample_entry(o, cache)?;
                Ok(e.preview
                    .get_or_init(|| {
                        let exact = ExactField::new(
                            vec![(e.field.clone(), CsgOp::Union)],
                            self.band() as f64,
                        );
                        Arc::new(stitch(&e.sampled.as_grid().extract_all(Some(&exact))))
                    })
                    .clone())
            })
            .collect()
    }

    /// [`Self::pending_previews_with`] the [`default_cache`], as owned
    /// meshes.
    pub fn pending_previews(&self) -> Result<Vec<TriMesh>, SdfError> {
        Ok(self
            .pending_previews_with(default_cache())?
            .iter()
            .map(|m| (**m).clone())
            .collect())
    }
}

fn check_budget(grid: &SparseGrid) -> Result<(), SdfError> {
    let b = grid.dense_bytes();
    if b > MEMORY_BUDGET_BYTES {
        return Err(SdfError::OverBudget(super::budget::grid_memory(
            super::budget::mib_ceil(b as f64),
            (MEMORY_BUDGET_BYTES >> 20) as u64,
        )));
    }
    Ok(())
}

/// The keys of the stored bricks `k` with `klo <= k <= khi` (integral
/// bounds) on every axis: through one range query per (x, y) column of the
/// box when it has fewer columns than the grid has bricks, so that an
/// update near a small operand does not walk the whole grid.
fn stored_in_box(grid: &SparseGrid, klo: [f64; 3], khi: [f64; 3]) -> Vec<BrickKey> {
    let inside = |k: &BrickKey| (0..3).all(|a| (k[a] as f64) >= klo[a] && (k[a] as f64) <= khi[a]);
    let columns = (0..2)
        .map(|a| (khi[a] - klo[a] + 1.0).max(0.0))
        .product::<f64>();
    let finite = klo.iter().chain(&khi).all(|v| v.is_finite());
    if !finite || columns >= grid.bricks.len() as f64 {
        return grid.bricks.keys().copied().filter(inside).collect();
    }
    // The bounds are integers within the columns' count of each other, so
    // in i32 range unless the grid's own keys are not (then `inside`
    // still decides).
    let [x0, y0, z0] = klo.map(|v| v.max(i32::MIN as f64) as i32);
    let [x1, y1, z1] = khi.map(|v| v.min(i32::MAX as f64) as i32);
    let mut out = Vec::new();
    if z0 > z1 {
        return out;
    }
    for x in x0..=x1 {
        for y in y0..=y1 {
            out.extend(
                grid.bricks
                    .range([x, y, z0]..=[x, y, z1])
                    .map(|(k, _)| *k)
                    .filter(inside),
            );
        }
    }
    out
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
