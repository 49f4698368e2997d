//! Patches filling loops of a curve network (paper §5.3).
//!
//! A 3- or 4-sided loop gets a bilinearly blended Coons patch of its sides
//! (a 3-sided loop is a Coons patch with one side collapsed to a point),
//! plus a bicubic B-spline displacement with a zero boundary, edited by the
//! surface tools; loops of more pieces are filled by [`super::ngon`].
//! Patches are G0 to their curves by construction. Meshing samples each
//! piece at canonical parameters and each node at one point, so
//! neighbouring patches share boundary vertices bit for bit and a closed
//! net welds into a closed 2-manifold.

use serde::{Deserialize, Serialize};

use crate::math::{DVec2, DVec3};
use crate::mesh::TriMesh;

use super::loops::Piece;
use super::network::CurveNetwork;
use super::polygon::NgonDomain;
use super::surface::{eval_grid, BaseDerivs, SurfaceSystem, SurfaceWeights};
use super::StylingError;

/// A surface filling a loop.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Patch {
    /// The loop, 3 to [`super::ngon::MAX_SIDES`] pieces head to tail.
    pub pieces: Vec<Piece>,
    /// Displacement control points (`surface_n × surface_n`, row `i`
    /// along `u`): boundary zero on 3- and 4-sided patches; weighted by
    /// the domain's weight function on n-sided ones ([`super::ngon`]).
    pub disp: Vec<[f64; 3]>,
}

/// Where a vertex of a patch's mesh comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum MeshSample {
    /// A boundary sample: on the patch's curves, whatever its displacement.
    Fixed(DVec3),
    /// The patch evaluated at this domain point (see
    /// [`CurveNetwork::patch_point`]).
    At(DVec2),
}

/// Triangles of an `m × m`-cell grid of `(m + 1)²` row-major vertices,
/// counter-clockwise in `(i, j)`.
pub(crate) fn grid_triangles(m: usize) -> Vec<[u32; 3]> {
    let idx = |i: usize, j: usize| (j * (m + 1) + i) as u32;
    let mut tris = Vec::with_capacity(2 * m * m);
    for j in 0..m {
        for i in 0..m {
            tris.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
            tris.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    tris
}

impl CurveNetwork {
    /// The piece as a function of `s ∈ [0, 1]`: derivatives 0..=2.
    fn piece_derivs(&self, p: &Piece, s: f64) -> [DVec3; 3] {
        let c = self.curves[p.curve].as_ref();
        let (ta, tb) = (
            self.param(p.from, p.curve).unwrap_or(0.0),
            self.param(p.to, p.curve).unwrap_or(0.0),
        );
        match c {
            Some(c) => {
                let d = c.derivs(ta + (tb - ta) * s, 2);
                let h = tb - ta;
                [d[0], d[1] * h, d[2] * h * h]
            }
            None => [DVec3::NAN; 3],
        }
    }

    /// The Coons base of patch `k` at `(u, v)`: `[s, s_u, s_v, s_uu, s_uv, s_vv]`.
    pub fn coons(&self, k: usize, u: f64, v: f64) -> BaseDerivs {
        let pc = &self.patches[k].pieces;
        let bot = self.piece_derivs(&pc[0], u);
        let right = self.piece_derivs(&pc[1], v);
        let t2 = self.piece_derivs(&pc[2], 1.0 - u);
        let top = [t2[0], -t2[1], t2[2]];
        let p00 = self.node_point(pc[0].from);
        let p10 = self.node_point(pc[1].from);
        let p11 = self.node_point(pc[2].from);
        let (left, p01) = if pc.len() == 4 {
            let l3 = self.piece_derivs(&pc[3], 1.0 - v);
            ([l3[0], -l3[1], l3[2]], self.node_point(pc[3].from))
        } else {
            ([p00, DVec3::ZERO, DVec3::ZERO], p00)
        };
        let s = (1.0 - v) * bot[0] + v * top[0] + (1.0 - u) * left[0] + u * right[0]
            - ((1.0 - u) * (1.0 - v) * p00
                + u * (1.0 - v) * p10
                + (1.0 - u) * v * p01
                + u * v * p11);
        let su = (1.0 - v) * bot[1] + v * top[1] - left[0] + right[0]
            - (-(1.0 - v) * p00 + (1.0 - v) * p10 - v * p01 + v * p11);
        let sv = -bot[0] + top[0] + (1.0 - u) * left[1] + u * right[1]
            - (-(1.0 - u) * p00 - u * p10 + (1.0 - u) * p01 + u * p11);
        let suu = (1.0 - v) * bot[2] + v * top[2];
        let svv = (1.0 - u) * left[2] + u * right[2];
        let suv = -bot[1] + top[1] - left[1] + right[1];
        [s, su, sv, suu, suv, svv]
    }

    /// Point of patch `k` at `(u, v)`: base plus displacement. For 3- and
    /// 4-sided patches `(u, v) ∈ [0, 1]²` are the Coons parameters; for
    /// n-sided ones, a point of the regular n-gon inscribed in the unit
    /// square ([`NgonDomain::regular`]; `(½, ½)` is the centre either way).
    pub fn patch_point(&self, k: usize, u: f64, v: f64) -> DVec3 {
        if self.patches[k].pieces.len() > 4 {
            return self.ngon_point(k, DVec2::new(u, v));
        }
        let n = self.surface_n as usize;
        self.coons(k, u, v)[0] + eval_grid(n, n, &self.patches[k].disp, u, v)
    }

    /// The base surface (without displacement) of patch `k` at `(u, v)`
    /// (parameters as in [`CurveNetwork::patch_point`]).
    pub fn patch_base_point(&self, k: usize, u: f64, v: f64) -> Result<DVec3, StylingError> {
        let sides = self.patch(k)?.pieces.len();
        Ok(if sides > 4 {
            let dom = NgonDomain::regular(sides);
            self.ngon_base(k, &dom, DVec2::new(u, v)).v
        } else {
            self.coons(k, u, v)[0]
        })
    }

    /// Patch `k`, or [`StylingError::NoPatch`].
    pub fn patch(&self, k: usize) -> Result<&Patch, StylingError> {
        self.patches.get(k).ok_or(StylingError::NoPatch(k))
    }

    /// The surface tools' energy of patch `k` (paper §4) with the weights
    /// `w`, on any patch: the Coons base and its bicubic displacement on 3-
    /// and 4-sided patches, the transfinite base and its weighted
    /// displacement on n-sided ones.
    pub fn surface_system(
        &self,
        k: usize,
        w: &SurfaceWeights,
    ) -> Result<SurfaceSystem, StylingError> {
        let sides = self.patch(k)?.pieces.len();
        let n = self.surface_n as usize;
        if sides > 4 {
            let dom = NgonDomain::regular(sides);
            let base = |p: DVec2| self.ngon_base(k, &dom, p);
            SurfaceSystem::on_ngon(n, &dom, w, &base)
        } else {
            let base = |u: f64, v: f64| self.coons(k, u, v);
            SurfaceSystem::new(n, n, w, Some(&base))
        }
    }

    /// Canonical sample `i` of `m` along a piece (shared by both patches
    /// that use the piece, whatever their direction).
    pub(crate) fn piece_sample(&self, p: &Piece, i: usize, m: usize) -> DVec3 {
        if i == 0 {
            return self.node_point(p.from);
        }
        if i == m {
            return self.node_point(p.to);
        }
        let (ta, tb) = (
            self.param(p.from, p.curve).unwrap_or(f64::NAN),
            self.param(p.to, p.curve).unwrap_or(f64::NAN),
        );
        let (lo, hi, k) = if ta <= tb {
            (ta, tb, i)
        } else {
            (tb, ta, m - i)
        };
        let t = lo + (hi - lo) * k as f64 / m as f64;
        self.curves[p.curve]
            .as_ref()
            .map(|c| c.point(t))
            .unwrap_or(DVec3::NAN)
    }

    /// Where each vertex of patch `k`'s mesh comes from (a boundary
    /// sample, or a domain point the patch is evaluated at) and the mesh's
    /// triangles: the mesh without evaluating the interior, so a held
    /// surface tool can evaluate it cheaply frame after frame
    /// ([`super::surface_hold`]).
    pub(crate) fn patch_samples(&self, k: usize) -> (Vec<MeshSample>, Vec<[u32; 3]>) {
        if self.patches[k].pieces.len() > 4 {
            return self.ngon_samples(k);
        }
        let m = self.resolution as usize;
        let pc = &self.patches[k].pieces;
        let mut out = Vec::with_capacity((m + 1) * (m + 1));
        for j in 0..=m {
            for i in 0..=m {
                let fixed = if j == 0 {
                    Some(self.piece_sample(&pc[0], i, m))
                } else if i == m {
                    Some(self.piece_sample(&pc[1], j, m))
                } else if j == m {
                    Some(self.piece_sample(&pc[2], m - i, m))
                } else if i == 0 {
                    Some(if pc.len() == 4 {
                        self.piece_sample(&pc[3], m - j, m)
                    } else {
                        self.node_point(pc[0].from)
                    })
                } else {
                    None
                };
                out.push(match fixed {
                    Some(p) => MeshSample::Fixed(p),
                    None => MeshSample::At(DVec2::new(i as f64 / m as f64, j as f64 / m as f64)),
                });
            }
        }
        (out, grid_triangles(m))
    }

    /// Triangle mesh of patch `k` (boundary vertices on the curves).
    pub fn patch_mesh(&self, k: usize) -> TriMesh {
        let (samples, triangles) = self.patch_samples(k);
        let sides = self.patches[k].pieces.len();
        let dom = (sides > 4).then(|| NgonDomain::regular(sides));
        let positions = samples
            .iter()
            .map(|s| {
                match *s {
                    MeshSample::Fixed(p) => p,
                    MeshSample::At(uv) => match &dom {
                        Some(d) => self.ngon_point_in(k, d, uv),
                        None => self.patch_point(k, uv.x, uv.y),
                    },
                }
                .to_array()
            })
            .collect();
        TriMesh::new(positions, triangles)
    }

    /// The mesh of every patch, welded; degenerate triangles (collapsed
    /// sides of 3-sided patches) removed; oriented outwards when closed.
    pub fn mesh(&self) -> TriMesh {
        let mut out = TriMesh::default();
        for k in 0..self.patches.len() {
            out.append(&self.patch_mesh(k));
        }
        out.weld_exact();
        let keep: Vec<bool> = out
            .triangles
            .iter()
            .map(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        let mut k = 0;
        out.triangles.retain(|_| {
            k += 1;
            keep[k - 1]
        });
        if out.tri_source.len() == keep.len() {
            let mut k = 0;
            out.tri_source.retain(|_| {
                k += 1;
                keep[k - 1]
            });
        }
        if out.signed_volume() < 0.0 {
            for t in &mut out.triangles {
                t.swap(1, 2);
            }
        }
        out.compute_normals();
        out
    }
}
