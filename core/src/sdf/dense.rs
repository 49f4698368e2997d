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

    /// The gradient of the trilinear interpolant at `p` (exact derivative
    /// of [`Self::sample`] inside a cell), or `None` outside the box. Sculpt
    /// brushes use it as the direction of explode/collapse warps.
    pub fn gradient(&self, p: DVec3) -> Option<DVec3> {
        let ([i, j, k], [x, y, z]) = self.locate(p)?;
        let c = |di: usize, dj: usize, dk: usize| self.at(i + di, j + dj, k + dk);
        let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
        let dx = lerp(
            lerp(c(1, 0, 0) - c(0, 0, 0), c(1, 1, 0) - c(0, 1, 0), y),
            lerp(c(1, 0, 1) - c(0, 0, 1), c(1, 1, 1) - c(0, 1, 1), y),
            z,
        );
        let dy = lerp(
            lerp(c(0, 1, 0) - c(0, 0, 0), c(1, 1, 0) - c(1, 0, 0), x),
            lerp(c(0, 1, 1) - c(0, 0, 1), c(1, 1, 1) - c(1, 0, 1), x),
            z,
        );
        let dz = lerp(
            lerp(c(0, 0, 1) - c(0, 0, 0), c(1, 0, 1) - c(1, 0, 0), x),
            lerp(c(0, 1, 1) - c(0, 1, 0), c(1, 1, 1) - c(1, 1, 0), x),
            y,
        );
        Some(DVec3::new(dx, dy, dz) / self.step)
    }
}
