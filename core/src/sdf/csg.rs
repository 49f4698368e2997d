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
//! rayon, results merged in key order), so the result does not depend on
//! the thread count. A brick whose centre is farther from the component's
//! surface than the brick's radius plus the band is uniform without
//! sampling its 512 points.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::grid::{local_index, Brick, BrickKey, SparseGrid, BRICK, BRICK_LEN};
use super::placement::PlacedField;
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

/// The component's clamped values over brick `key`.
pub fn component_brick(grid: &SparseGrid, f: &PlacedField, key: BrickKey) -> Brick {
    let h = grid.step;
    let band = grid.band as f64;
    let base = DVec3::new(key[0] as f64, key[1] as f64, key[2] as f64) * BRICK as f64;
    let centre = (base + DVec3::splat((BRICK - 1) as f64 / 2.0)) * h;
    let radius = (BRICK - 1) as f64 / 2.0 * 3f64.sqrt() * h;
    if let Some(s) = f.far_sign(centre, radius, band) {
        return Brick::Uniform(if s < 0.0 { -grid.band } else { grid.band });
    }
    // Not provably uniform as a whole: try 4³ octants, then 2³ blocks,
    // then sample.
    let mut d = vec![0f32; BRICK_LEN];
    fill_block(grid, f, base, [0; 3], BRICK, &mut d);
    Brick::dense(d, grid.band)
}

/// Fills the `size`³ block at local offset `o` of the brick at sample
/// `base`: uniform when the far test proves it, else split in 8 down to
/// 2³ blocks, else sampled.
fn fill_block(
    grid: &SparseGrid,
    f: &PlacedField,
    base: DVec3,
    o: [i32; 3],
    size: i32,
    d: &mut [f32],
) {
    let h = grid.step;
    let band = grid.band as f64;
    let half = size / 2;
    for oct in 0..8 {
        let so = [oct & 1, oct >> 1 & 1, oct >> 2 & 1].map(|b| b * half);
        let so = [o[0] + so[0], o[1] + so[1], o[2] + so[2]];
        let c = (base
            + DVec3::new(so[0] as f64, so[1] as f64, so[2] as f64)
            + DVec3::splat((half - 1) as f64 / 2.0))
            * h;
        let r = (half - 1) as f64 / 2.0 * 3f64.sqrt() * h;
        if let Some(s) = f.far_sign(c, r, band) {
            let u = if s < 0.0 { -grid.band } else { grid.band };
            for z in so[2]..so[2] + half {
                for y in so[1]..so[1] + half {
                    for x in so[0]..so[0] + half {
                        d[local_index(x, y, z)] = u;
                    }
                }
            }
        } else if half > 2 {
            fill_block(grid, f, base, so, half, d);
        } else {
            for z in so[2]..so[2] + half {
                for y in so[1]..so[1] + half {
                    for x in so[0]..so[0] + half {
                        let p = (base + DVec3::new(x as f64, y as f64, z as f64)) * h;
                        d[local_index(x, y, z)] =
                            f.value(p).map_or(band, |v| v.clamp(-band, band)) as f32;
                    }
                }
            }
        }
    }
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

/// Fuses `f` into `grid` with `op`; returns the keys of the bricks whose
/// samples changed, sorted.
pub fn fuse(grid: &mut SparseGrid, f: &PlacedField, op: CsgOp) -> Vec<BrickKey> {
    let (lo, hi) = f.world_box;
    let mut region = bricks_in_box(grid.step, lo, hi);
    if op == CsgOp::Subtract {
        region.retain(|k| grid.bricks.contains_key(k));
    }
    let g: &SparseGrid = grid;
    let results: Vec<(BrickKey, Option<Brick>)> = region
        .par_iter()
        .with_min_len(4)
        .map(|&k| {
            let old = g.brick(k);
            let comp = component_brick(g, f, k);
            let new = combine(op, &old, &comp, g.band);
            (k, (new != old).then_some(new))
        })
        .collect();
    let mut changed = Vec::new();
    if op == CsgOp::Intersect {
        let (rlo, rhi) = (
            region.first().copied().unwrap_or([0; 3]),
            region.last().copied().unwrap_or([-1; 3]),
        );
        let outside: Vec<BrickKey> = grid
            .bricks
            .keys()
            .filter(|k| (0..3).any(|a| k[a] < rlo[a] || k[a] > rhi[a]))
            .copied()
            .collect();
        for k in outside {
            grid.bricks.remove(&k);
            changed.push(k);
        }
    }
    for (k, new) in results {
        if let Some(b) = new {
            grid.set(k, b);
            changed.push(k);
        }
    }
    changed.sort_unstable();
    changed
}
