//! Voxel-wise CSG of a placed component into the scene grid (paper 2 §5.3,
//! eqs. 7–8), brick-parallel (§5.4's 8×8×8 work groups, on CPU threads).
//!
//! Restricted regions (eq. 8), as they follow from clamped fields:
//! - union `min(a, b)`: only bricks meeting the component's box `D₂` can
//!   change (outside it `b = +band`);
//! - intersect `max(a, b)`: inside `D₁ ∩ D₂` computed voxel-wise; every
//!   stored brick outside `D₂` becomes outside (dropped);
//! - subtract `max(a, −b)`: only bricks of `D₁` meeting `D₂` can change.
//!
//! Each brick of the region is evaluated independently (in parallel with
//! rayon over fixed chunks, results merged in key order), so the result
//! does not depend on the thread count. The operand's values come from
//! [`super::sample`], resampled once per placement and reused; the fold
//! itself is a min/max over bricks, bound by memory bandwidth.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::grid::{Brick, BrickKey, SparseGrid, BRICK, BRICK_LEN};
use super::placement::PlacedField;
use super::sample::{sample_operand, SampledOperand, CHUNK};
use crate::math::DVec3;

/// A CSG operation of the SceneOperate mode (paper §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CsgOp {
    /// `min(a, b)`.
    Union,
    /// `max(a, b)`.
    Intersect,
    /// `max(a, -b)`.
    Subtract,
}

/// The bricks meeting the world box `(lo, hi)`, in key order.
pub fn bricks_in_box(step: f64, lo: DVec3, hi: DVec3) -> Vec<BrickKey> {
    let b = BRICK as f64 * step;
    let kl = (lo / b).floor();
    let kh = (hi / b).floor();
    let mut out = Vec::new();
    for z in kl.z as i32..=kh.z as i32 {
        for y in kl.y as i32..=kh.y as i32 {
            for x in kl.x as i32..=kh.x as i32 {
                out.push([x, y, z]);
            }
        }
    }
    out
}

/// Number of bricks meeting the world box (without listing them).
pub fn brick_count_in_box(step: f64, lo: DVec3, hi: DVec3) -> f64 {
    let b = BRICK as f64 * step;
    let n = (hi / b).floor() - (lo / b).floor() + DVec3::ONE;
    n.x * n.y * n.z
}

fn combine(op: CsgOp, a: &Brick, b: &Brick, band: f32) -> Brick {
    let f = |x: f32, y: f32| match op {
        CsgOp::Union => x.min(y),
        CsgOp::Intersect => x.max(y),
        CsgOp::Subtract => x.max(-y),
    };
    match (a, b) {
        (Brick::Uniform(x), Brick::Uniform(y)) => Brick::Uniform(f(*x, *y)),
        _ => {
            let d: Vec<f32> = (0..BRICK_LEN).map(|l| f(a.get(l), b.get(l))).collect();
            Brick::dense(d, band)
        }
    }
}

/// Fuses `f` into `grid` with `op`: resamples it ([`sample_operand`])
/// and folds it in ([`fuse_sampled`]); returns the keys of the bricks
/// whose samples changed, sorted.
pub fn fuse(grid: &mut SparseGrid, f: &PlacedField, op: CsgOp) -> Vec<BrickKey> {
    let s = sample_operand(f, grid.step, grid.band);
    fuse_sampled(grid, &s, op)
}

/// Folds a resampled operand into `grid` with `op` (eq. 7) over the
/// bricks that can change (eq. 8 as it follows from clamped fields):
/// union and subtract touch only the operand's stored bricks (elsewhere
/// it is `+band`: `min(a, +band) = a`, `max(a, -band) = a`); intersect
/// touches only the grid's stored bricks (`max(a, +band)` empties every
/// one the operand does not cover). Brick-parallel in fixed chunks,
/// merged in key order: the same bits on any thread count. Returns the
/// keys of the bricks whose samples changed, sorted.
pub fn fuse_sampled(grid: &mut SparseGrid, s: &SampledOperand, op: CsgOp) -> Vec<BrickKey> {
    debug_assert_eq!((grid.step, grid.band), (s.step, s.band));
    let g: &SparseGrid = grid;
    let band = g.band;
    let results: Vec<(BrickKey, Option<Brick>)> = match op {
        CsgOp::Union | CsgOp::Subtract => s
            .bricks
            .par_chunks(CHUNK)
            .flat_map_iter(|chunk| {
                chunk.iter().filter_map(|(k, b)| {
                    let old = g.bricks.get(k);
                    if op == CsgOp::Subtract && old.is_none() {
                        return None;
                    }
                    let old = old.cloned().unwrap_or(Brick::Uniform(band));
                    let new = combine(op, &old, b, band);
                    Some((*k, (new != old).then_some(new)))
                })
            })
            .collect(),
        CsgOp::Intersect => {
            let stored: Vec<(&BrickKey, &Brick)> = g.bricks.iter().collect();
            stored
                .par_chunks(CHUNK)
                .flat_map_iter(|chunk| {
                    chunk.iter().map(|(k, old)| {
                        let new = match s.brick(**k) {
                            Some(b) => combine(op, old, b, band),
                            None => Brick::Uniform(band),
                        };
                        (**k, (new != **old).then_some(new))
                    })
                })
                .collect()
        }
    };
    let mut changed = Vec::new();
    for (k, new) in results {
        if let Some(b) = new {
            grid.set(k, b);
            changed.push(k);
        }
    }
    changed
}
