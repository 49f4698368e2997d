//! n-sided patches (n = 5..=[`MAX_SIDES`]) by central splitting.
//!
//! Method (a standard quad split, as for Catmull-Clark faces): the loop's
//! `n` pieces are cut at their middles `M_k` (piece `k` at `s = 1/2`), a
//! centre `C` is taken as the mean of the `n` nodes `V_k` and the `n`
//! middles, and the loop becomes `n` quads `V_k, M_k, C, M_{k-1}`, each a
//! bilinearly blended Coons patch of four sides: the first half of piece
//! `k`, the straight spoke `M_k → C`, the spoke `C ← M_{k-1}` and the second
//! half of piece `k-1`. Each quad interpolates its boundary, so the patch is
//! G0 to the loop's curves (and the quads are G0 to each other along the
//! spokes). The surface tools' displacement is not defined on these
//! patches: they are refused there with [`StylingError::NotQuad`].
//!
//! Meshing: each quad is an `h × h` grid with `h = resolution / 2` (the
//! resolution must be even, so that a piece's middle is one of its
//! canonical samples and an n-gon shares boundary vertices bit for bit
//! with the patches on the other side of its pieces). Spoke samples are
//! computed once per spoke, so neighbouring quads share them exactly.

use crate::math::DVec3;
use crate::mesh::TriMesh;

use super::network::{CurveNetwork, Piece};
use super::patch::grid_triangles;
use super::StylingError;

/// The largest loop (in pieces) that can be filled.
pub const MAX_SIDES: usize = 8;

impl CurveNetwork {
    /// Piece `p` at `s ∈ [0, 1]` along its direction.
    fn piece_at(&self, p: &Piece, s: f64) -> DVec3 {
        let (Some(ta), Some(tb)) = (self.param(p.from, p.curve), self.param(p.to, p.curve)) else {
            return DVec3::NAN;
        };
        match self.curves.get(p.curve).and_then(|c| c.as_ref()) {
            Some(c) => c.point(ta + (tb - ta) * s),
            None => DVec3::NAN,
        }
    }

    /// Middles `M_k` (canonical sample `m/2` of each piece) and the centre.
    fn ngon_frame(&self, k: usize) -> (Vec<DVec3>, DVec3) {
        let pc = &self.patches[k].pieces;
        let m = self.resolution as usize;
        let mids: Vec<DVec3> = pc.iter().map(|p| self.piece_sample(p, m / 2, m)).collect();
        let sum: DVec3 = pc.iter().map(|p| self.node_point(p.from)).sum::<DVec3>()
            + mids.iter().copied().sum::<DVec3>();
        (mids, sum / (2 * pc.len()) as f64)
    }

    /// Point of quad `q` of the n-sided patch `k` at `(u, v) ∈ [0, 1]²`:
    /// `u` runs from `V_q` to `M_q`, `v` from `V_q` to `M_{q-1}`.
    pub fn ngon_point(&self, k: usize, q: usize, u: f64, v: f64) -> DVec3 {
        let pc = &self.patches[k].pieces;
        let n = pc.len();
        let (mids, c) = self.ngon_frame(k);
        let prev = (q + n - 1) % n;
        let p00 = self.node_point(pc[q].from);
        let (p10, p01) = (mids[q], mids[prev]);
        let bottom = self.piece_at(&pc[q], 0.5 * u);
        let left = self.piece_at(&pc[prev], 1.0 - 0.5 * v);
        let right = p10.lerp(c, v);
        let top = p01.lerp(c, u);
        (1.0 - v) * bottom + v * top + (1.0 - u) * left + u * right
            - ((1.0 - u) * (1.0 - v) * p00 + u * (1.0 - v) * p10 + (1.0 - u) * v * p01 + u * v * c)
    }

    /// Triangle mesh of the n-sided patch `k`: `n` quads of `h × h` cells.
    pub(crate) fn ngon_mesh(&self, k: usize) -> TriMesh {
        let pc = self.patches[k].pieces.clone();
        let n = pc.len();
        let m = self.resolution as usize;
        let h = m / 2;
        let (mids, c) = self.ngon_frame(k);
        // Spoke j sample i: from M_j (i = 0) to C (i = h).
        let spoke = |j: usize, i: usize| {
            if i == 0 {
                mids[j]
            } else if i == h {
                c
            } else {
                mids[j].lerp(c, i as f64 / h as f64)
            }
        };
        let mut out = TriMesh::default();
        for q in 0..n {
            let prev = (q + n - 1) % n;
            let mut pos = Vec::with_capacity((h + 1) * (h + 1));
            for j in 0..=h {
                for i in 0..=h {
                    let p = if j == 0 {
                        self.piece_sample(&pc[q], i, m)
                    } else if i == 0 {
                        self.piece_sample(&pc[prev], m - j, m)
                    } else if i == h {
                        spoke(q, j)
                    } else if j == h {
                        spoke(prev, i)
                    } else {
                        self.ngon_point(k, q, i as f64 / h as f64, j as f64 / h as f64)
                    };
                    pos.push(p.to_array());
                }
            }
            out.append(&TriMesh::new(pos, grid_triangles(h)));
        }
        out
    }

    /// Checks that an n-sided loop can be meshed (even resolution).
    pub(crate) fn check_ngon(&self, sides: usize) -> Result<(), StylingError> {
        if sides > 4 && !self.resolution.is_multiple_of(2) {
            return Err(StylingError::OddResolution(self.resolution));
        }
        Ok(())
    }
}
