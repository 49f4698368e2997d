//! [`DenseSdf`]: a component's precomputed discrete SDF (paper 2 §5.2) on a
//! regular grid, sampled by trilinear interpolation (eqs. 5–6).

use serde::{Deserialize, Serialize};

use crate::math::DVec3;

/// A signed distance field sampled on a regular grid in the component's
/// local frame. Sample `(i, j, k)` sits at `origin + step * (i, j, k)` and
/// is stored at `i + dims[0] * (j + dims[1] * k)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DenseSdf {
    /// Samples per axis (each at least 2).
    pub dims: [usize; 3],
    /// Position of sample `(0, 0, 0)`.
    pub origin: [f64; 3],
    /// Grid spacing.
    pub step: f64,
    /// Signed distances, negative inside.
    pub values: Vec<f32>,
}

impl DenseSdf {
    /// The far corner of the grid's box.
    pub fn max_corner(&self) -> DVec3 {
        DVec3::from_array(self.origin)
            + DVec3::new(
                (self.dims[0] - 1) as f64,
                (self.dims[1] - 1) as f64,
                (self.dims[2] - 1) as f64,
            ) * self.step
    }

    /// The grid's box `(min, max)`.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        (DVec3::from_array(self.origin), self.max_corner())
    }

    #[inline]
    fn at(&self, i: usize, j: usize, k: usize) -> f64 {
        self.values[i + self.dims[0] * (j + self.dims[1] * k)] as f64
    }

    /// Cell index and fractions of `p`, or `None` outside the grid's box.
    #[inline]
    fn locate(&self, p: DVec3) -> Option<([usize; 3], [f64; 3])> {
        let mut idx = [0usize; 3];
        let mut fr = [0.0; 3];
        for a in 0..3 {
            let u = (p[a] - self.origin[a]) / self.step;
            let n = self.dims[a] - 1;
            if !(u >= 0.0 && u <= n as f64) {
                return None;
            }
            let i = (u.floor() as usize).min(n - 1);
            idx[a] = i;
            fr[a] = u - i as f64;
        }
        Some((idx, fr))
    }

    /// Trilinear interpolation at `p` (paper eq. 6), or `None` outside the
    /// grid's box (where the paper sets +infinity).
    #[inline]
    pub fn sample(&self, p: DVec3) -> Option<f64> {
        let ([i, j, k], [x, y, z]) = self.locate(p)?;
        let c = |di: usize, dj: usize, dk: usize| self.at(i + di, j + dj, k + dk);
        let x00 = c(0, 0, 0) + (c(1, 0, 0) - c(0, 0, 0)) * x;
        let x10 = c(0, 1, 0) + (c(1, 1, 0) - c(0, 1, 0)) * x;
        let x01 = c(0, 0, 1) + (c(1, 0, 1) - c(0, 0, 1)) * x;
        let x11 = c(0, 1, 1) + (c(1, 1, 1) - c(0, 1, 1)) * x;
        let y0 = x00 + (x10 - x00) * y;
        let y1 = x01 + (x11 - x01) * y;
        Some(y0 + (y1 - y0) * z)
    }

    /// The cell and fractions of grid index coordinates `u`, or `None`
    /// outside the grid (no division, no `floor` call: the caller already
    /// works in index units).
    #[inline]
    fn locate_index(&self, u: DVec3) -> Option<(usize, [f64; 3])> {
        let mut c = 0usize;
        let mut fr = [0.0; 3];
        let mut stride = 1usize;
        for (a, f) in fr.iter_mut().enumerate() {
            let n = self.dims[a] - 1;
            if !(u[a] >= 0.0 && u[a] <= n as f64) {
                return None;
            }
            // Truncation is the floor: u is at least 0.
            let i = (u[a] as usize).min(n - 1);
            *f = u[a] - i as f64;
            c += i * stride;
            stride *= self.dims[a];
        }
        Some((c, fr))
    }

    /// The 8 corners of cell `c` (corner `i` at offset `(i & 1, i >> 1 &
    /// 1, i >> 2 & 1)`).
    #[inline]
    fn corners(&self, c: usize) -> [f64; 8] {
        let (nx, nxy) = (self.dims[0], self.dims[0] * self.dims[1]);
        let w = &self.values[c..c + nxy + nx + 2];
        [
            w[0],
            w[1],
            w[nx],
            w[nx + 1],
            w[nxy],
            w[nxy + 1],
            w[nxy + nx],
            w[nxy + nx + 1],
        ]
        .map(f64::from)
    }

    /// Trilinear interpolation at grid index coordinates `u` (what
    /// [`Self::sample`] does at `origin + step · u`), or `None` outside.
    #[inline]
    pub fn sample_index(&self, u: DVec3) -> Option<f64> {
        let (c, [x, y, z]) = self.locate_index(u)?;
        let v = self.corners(c);
        let x00 = v[0] + (v[1] - v[0]) * x;
        let x10 = v[2] + (v[3] - v[2]) * x;
        let x01 = v[4] + (v[5] - v[4]) * x;
        let x11 = v[6] + (v[7] - v[6]) * x;
        let y0 = x00 + (x10 - x00) * y;
        let y1 = x01 + (x11 - x01) * y;
        Some(y0 + (y1 - y0) * z)
    }

    /// [`Self::sample_index`] and the interpolant's gradient in index
    /// units (divide by `step` for local units).
    #[inline]
    pub fn sample_gradient_index(&self, u: DVec3) -> Option<(f64, DVec3)> {
        let (c, f) = self.locate_index(u)?;
        let v = self.corners(c);
        let [x, y, z] = f;
        let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
        let y0 = lerp(lerp(v[0], v[1], x), lerp(v[2], v[3], x), y);
        let y1 = lerp(lerp(v[4], v[5], x), lerp(v[6], v[7], x), y);
        // ∂/∂z is y1 - y0, at hand: the shared formula's value up to
        // rounding, and the bits every SDF fixture was recorded with.
        let [gx, gy, _] = trilinear_gradient(&v, f);
        Some((lerp(y0, y1, z), DVec3::new(gx, gy, y1 - y0)))
    }

    /// The gradient of the trilinear interpolant at `p` (exact derivative
    /// of [`Self::sample`] inside a cell), or `None` outside the box. Sculpt
    /// brushes use it as the direction of explode/collapse warps.
    pub fn gradient(&self, p: DVec3) -> Option<DVec3> {
        let ([i, j, k], f) = self.locate(p)?;
        let v =
            [0, 1, 2, 3, 4, 5, 6, 7].map(|n| self.at(i + (n & 1), j + (n >> 1 & 1), k + (n >> 2)));
        Some(DVec3::from_array(trilinear_gradient(&v, f)) / self.step)
    }
}

/// The gradient of the trilinear interpolant of a cell's samples `v`
/// (corner `n` at offset `(n & 1, n >> 1 & 1, n >> 2 & 1)`) at the local
/// fractions `f`, in units of 1/step: the exact derivative inside the
/// cell, for the grids here and for extraction's bricks.
#[inline]
pub(crate) fn trilinear_gradient(v: &[f64; 8], [x, y, z]: [f64; 3]) -> [f64; 3] {
    let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
    let gx = lerp(
        lerp(v[1] - v[0], v[3] - v[2], y),
        lerp(v[5] - v[4], v[7] - v[6], y),
        z,
    );
    let gy = lerp(
        lerp(v[2] - v[0], v[3] - v[1], x),
        lerp(v[6] - v[4], v[7] - v[5], x),
        z,
    );
    let gz = lerp(
        lerp(v[4] - v[0], v[5] - v[1], x),
        lerp(v[6] - v[2], v[7] - v[3], x),
        y,
    );
    [gx, gy, gz]
}

/// Cells per side of a [`GridField`] bounds block.
const BOUND_BLOCK: usize = 2;

/// A component's grid ready for fast resampling: the SDF and, per block of
/// 2³ cells, the least and greatest sample (the trilinear interpolant of
/// a cell never leaves its corners' range), so that the fusion can prove
/// a whole brick far from the surface with a few lookups instead of the
/// Lipschitz bound's √3 slack.
#[derive(Clone, Debug, PartialEq)]
pub struct GridField {
    /// The grid.
    pub sdf: std::sync::Arc<DenseSdf>,
    /// Blocks per axis.
    blocks: [usize; 3],
    /// Per block: least and greatest sample of its cells' corners.
    ranges: Vec<[f32; 2]>,
    /// The area of the surface the grid samples, in its own units² (for
    /// the budgets, [`super::budget`]).
    pub surface_area: f64,
}

impl GridField {
    /// Precomputes the block ranges of `sdf`, whose surface has
    /// `surface_area` (its own units²).
    pub fn new(sdf: std::sync::Arc<DenseSdf>, surface_area: f64) -> Self {
        let cells = sdf.dims.map(|d| d - 1);
        let blocks = cells.map(|c| c.div_ceil(BOUND_BLOCK));
        let mut ranges =
            vec![[f32::INFINITY, f32::NEG_INFINITY]; blocks[0] * blocks[1] * blocks[2]];
        let [nx, ny, nz] = sdf.dims;
        for k in 0..nz {
            let bk: [usize; 2] = [
                k.saturating_sub(1) / BOUND_BLOCK,
                k.min(cells[2] - 1) / BOUND_BLOCK,
            ];
            for j in 0..ny {
                let bj = [
                    j.saturating_sub(1) / BOUND_BLOCK,
                    j.min(cells[1] - 1) / BOUND_BLOCK,
                ];
                for i in 0..nx {
                    let bi = [
                        i.saturating_sub(1) / BOUND_BLOCK,
                        i.min(cells[0] - 1) / BOUND_BLOCK,
                    ];
                    let v = sdf.values[i + nx * (j + ny * k)];
                    // A sample is a corner of the cells on both sides of
                    // it, which may lie in two blocks per axis.
                    for &c in &bk[..1 + (bk[0] != bk[1]) as usize] {
                        for &b in &bj[..1 + (bj[0] != bj[1]) as usize] {
                            for &a in &bi[..1 + (bi[0] != bi[1]) as usize] {
                                let r = &mut ranges[a + blocks[0] * (b + blocks[1] * c)];
                                r[0] = r[0].min(v);
                                r[1] = r[1].max(v);
                            }
                        }
                    }
                }
            }
        }
        Self {
            sdf,
            blocks,
            ranges,
            surface_area,
        }
    }

    /// The least and greatest value of the interpolant over the cells
    /// meeting the box `lo..=hi` in grid index units (clamped to the grid),
    /// or `None` when the box misses the grid.
    pub fn range(&self, lo: DVec3, hi: DVec3) -> Option<[f32; 2]> {
        let mut b0 = [0usize; 3];
        let mut b1 = [0usize; 3];
        for a in 0..3 {
            let n = (self.sdf.dims[a] - 1) as f64;
            if !(hi[a] >= 0.0 && lo[a] <= n) {
                return None;
            }
            // Truncation is the floor here: both are at least 0.
            let c0 = lo[a].max(0.0) as usize;
            let c1 = (hi[a].min(n) as usize).min(self.sdf.dims[a] - 2);
            b0[a] = c0.min(self.sdf.dims[a] - 2) / BOUND_BLOCK;
            b1[a] = c1 / BOUND_BLOCK;
        }
        let mut r = [f32::INFINITY, f32::NEG_INFINITY];
        for c in b0[2]..=b1[2] {
            for b in b0[1]..=b1[1] {
                let row = self.blocks[0] * (b + self.blocks[1] * c);
                for x in &self.ranges[row + b0[0]..=row + b1[0]] {
                    r[0] = r[0].min(x[0]);
                    r[1] = r[1].max(x[1]);
                }
            }
        }
        Some(r)
    }
}
