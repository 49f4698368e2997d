//! Multi-sided patches (5 to [`MAX_SIDES`] sides) that are smooth inside
//! (paper §5.3: Kuriyama's patches from `m` surrounding curves, by
//! transfinite interpolation of neighbouring curves and blending).
//!
//! **Base surface.** A side-based transfinite patch over a regular n-gon
//! domain (Várady, Rockwood, Salvi 2011; Kato's blends): for side `k`
//! (piece `P_k`, reparameterized to `[0, 1]` from its `from` node) the
//! ribbon
//!
//! ```text
//! R_k(p) = P_k(t_k) + d_k c (N × (Q_{k+1} - Q_k))
//! ```
//!
//! leaves the side across its chord in the loop's plane (`N` the loop's
//! Newell normal, `t_k` the projection of `p` on side `k`, the piece
//! continued past its ends by its end quadratics, `c` the domain's
//! inradius over its side length), and the patch blends them,
//! `S(p) = Σ_k μ_k(p) R_k(p)`, with the side blends `μ_k ∝ 1 / d_k²` of
//! [`NgonDomain`]. On side `k` only `μ_k` is non-zero and `d_k = 0`, so the
//! patch contains its boundary curves exactly (to the junction gap and
//! rounding; tests check 1e-9). Every function involved is C∞ inside the
//! polygon, so the patch is smooth in its interior: there are no internal
//! seams in the surface, only in its meshing, and normals are continuous
//! across the mesh's spokes by construction (tests measure them from both
//! sides). A corner-based patch (corner interpolants
//! `P_{k-1}(s_{k-1}) + P_k(s_k) - Q_k`, what this module did before)
//! stays, to first order near corner `k`, in the cone of the two pieces'
//! tangents there, which at a reflex corner (bowed sides) is outside the
//! loop: bowed 12- to 16-gons folded at their corners (issue 33). Kato's
//! blends depend on the direction a corner is approached from, so the
//! side-based patch opens a corner as wide as its curves do.
//!
//! **Why this and not subdivision or a split into quads.** The boundary
//! pieces are non-uniform cubic B-splines cut at arbitrary parameters: a
//! Catmull-Clark surface cannot contain them exactly, and a split into
//! quads with Coons sub-patches (what this module did before) is only G0
//! across the spokes (visible creases). A transfinite patch interpolates
//! any boundary exactly and is smooth inside by construction; it is cheap
//! to evaluate (one evaluation per piece per point).
//!
//! **Surface tools.** The styling displacement of an n-sided patch is
//! `D(p) = w(p) Σ N_i(x) N_j(y) d_ij`: the same clamped uniform bicubic
//! B-spline grid (`surface_n²` control points) as on quad patches, over
//! the unit square around the polygon, multiplied by a weight `w` that is
//! smooth and zero on every side (Höllig's weighted B-splines). `D` is zero
//! on the boundary whatever the coefficients, and smooth inside, so the
//! tools keep the patch on its curves and smooth. Coefficients whose
//! Greville point lies outside the polygon are fixed at zero. The energy
//! is integrated over the polygon (see [`NgonDomain::cell_quadrature`]),
//! with exact second derivatives by [`super::jet`].
//!
//! Meshing: the polygon is cut into `n` quads `V_k, M_k, C, M_{k-1}` (a
//! piece's middle `M_k`, the centre `C`), each an `h × h` grid with
//! `h = resolution / 2`, mapped bilinearly into the domain and then by
//! `S + D`. The resolution must be even, so that a piece's middle is one of
//! its canonical samples and the patch shares boundary vertices bit for
//! bit with the patches on the other side of its pieces. Spoke samples are
//! computed once per spoke, so neighbouring quads share them exactly.
//! 3- and 4-sided loops keep their Coons patches ([`super::patch`]), which
//! are smooth inside too and convert exactly to one NURBS surface for USD.

use crate::math::{DVec2, DVec3};

use super::jet::VJet;
use super::network::{CurveNetwork, Piece};
use super::patch::{grid_triangles, MeshSample};
use super::polygon::NgonDomain;
use super::surface::eval_grid;
use super::StylingError;

/// The largest loop (in pieces) that can be filled.
pub const MAX_SIDES: usize = 16;

/// The domain point of quad `q`'s chart at `(a, b) ∈ [0, 1]²`: `a` runs
/// from `V_q` to `M_q`, `b` from `V_q` to `M_{q-1}`.
pub fn ngon_chart(dom: &NgonDomain, q: usize, a: f64, b: f64) -> DVec2 {
    let n = dom.sides();
    let (v, m, c, mp) = (
        dom.vertex(q),
        dom.mid(q),
        dom.centre(),
        dom.mid((q + n - 1) % n),
    );
    v * ((1.0 - a) * (1.0 - b)) + m * (a * (1.0 - b)) + c * (a * b) + mp * ((1.0 - a) * b)
}

impl CurveNetwork {
    /// Piece `p` at `s ∈ [0, 1]` along its direction: derivatives 0..=2.
    fn piece_jet_values(&self, p: &Piece, s: f64) -> [DVec3; 3] {
        let (Some(ta), Some(tb)) = (self.param(p.from, p.curve), self.param(p.to, p.curve)) else {
            return [DVec3::NAN; 3];
        };
        match self.curves.get(p.curve).and_then(|c| c.as_ref()) {
            Some(c) => {
                let h = tb - ta;
                let d = c.derivs(ta + h * s.clamp(0.0, 1.0), 2);
                [d[0], d[1] * h, d[2] * h * h]
            }
            None => [DVec3::NAN; 3],
        }
    }

    /// Piece `p` at any `s` along its direction, derivatives 0..=2: the
    /// piece itself on `[0, 1]`, continued past its ends by the quadratic
    /// with its end's value and first two derivatives (so it is C² at the
    /// ends).
    fn piece_extended(&self, p: &Piece, s: f64) -> [DVec3; 3] {
        let (end, t) = if s < 0.0 {
            (0.0, s)
        } else if s > 1.0 {
            (1.0, s - 1.0)
        } else {
            return self.piece_jet_values(p, s);
        };
        let [v, d1, d2] = self.piece_jet_values(p, end);
        [v + d1 * t + d2 * (0.5 * t * t), d1 + d2 * t, d2]
    }

    /// The unit normal of patch `k`'s loop (Newell's, over its nodes and
    /// the middles of its pieces; zero for a loop without one): the loop
    /// runs counter-clockwise around it.
    fn loop_normal(&self, pc: &[Piece]) -> DVec3 {
        let pts: Vec<DVec3> = pc
            .iter()
            .flat_map(|p| [self.node_point(p.from), self.piece_jet_values(p, 0.5)[0]])
            .collect();
        let n = pts.len();
        (0..n)
            .map(|i| pts[i].cross(pts[(i + 1) % n]))
            .fold(DVec3::ZERO, |a, b| a + b)
            .normalize_or_zero()
    }

    /// The transfinite base of the n-sided patch `k` at domain point `p`,
    /// with its first and second derivatives in the domain coordinates.
    pub fn ngon_base(&self, k: usize, dom: &NgonDomain, p: DVec2) -> VJet {
        let pc = &self.patches[k].pieces;
        let d = dom.dists(p);
        let up = self.loop_normal(pc);
        let c = dom.ribbon_scale();
        let blends = NgonDomain::side_blends(&d);
        let mut out = VJet::default();
        for (j, (piece, b)) in pc.iter().zip(&blends).enumerate() {
            let s = dom.along(p, j);
            let side = s.compose_curve(self.piece_extended(piece, s.v));
            // The ribbon's direction: across the piece's chord, in the
            // loop's plane.
            let chord = self.node_point(piece.to) - self.node_point(piece.from);
            let across = VJet::constant(up.cross(chord) * c);
            let ribbon = side + across.scale(d[j]);
            out = out + ribbon.scale(*b);
        }
        out
    }

    /// The displacement of the n-sided patch `k` at domain point `p`
    /// (zero for a patch stored without one).
    pub fn ngon_displacement(&self, k: usize, dom: &NgonDomain, p: DVec2) -> DVec3 {
        let n = self.surface_n as usize;
        let disp = &self.patches[k].disp;
        if disp.len() != n * n {
            return DVec3::ZERO;
        }
        let w = NgonDomain::weight(&dom.dists(p)).v;
        if w == 0.0 {
            return DVec3::ZERO;
        }
        eval_grid(n, n, disp, p.x, p.y) * w
    }

    /// Point of the n-sided patch `k` at domain point `p` (inside the
    /// regular n-gon of [`NgonDomain::regular`]).
    pub fn ngon_point(&self, k: usize, p: DVec2) -> DVec3 {
        let dom = NgonDomain::regular(self.patches[k].pieces.len());
        self.ngon_base(k, &dom, p).v + self.ngon_displacement(k, &dom, p)
    }

    pub(crate) fn ngon_point_in(&self, k: usize, dom: &NgonDomain, p: DVec2) -> DVec3 {
        self.ngon_base(k, dom, p).v + self.ngon_displacement(k, dom, p)
    }

    /// The mesh samples of the n-sided patch `k` (see
    /// [`CurveNetwork::patch_samples`]): `n` quads of `h × h` cells, each
    /// its own grid (the network's mesh welds them).
    pub(crate) fn ngon_samples(&self, k: usize) -> (Vec<MeshSample>, Vec<[u32; 3]>) {
        let pc = self.patches[k].pieces.clone();
        let n = pc.len();
        let m = self.resolution as usize;
        let h = m / 2;
        let dom = NgonDomain::regular(n);
        // Spoke j sample i: from M_j (i = 0) to C (i = h).
        let spoke = |j: usize, i: usize| {
            if i == 0 {
                MeshSample::Fixed(self.piece_sample(&pc[j], m / 2, m))
            } else if i == h {
                MeshSample::At(dom.centre())
            } else {
                MeshSample::At(dom.mid(j).lerp(dom.centre(), i as f64 / h as f64))
            }
        };
        let mut out = Vec::with_capacity(n * (h + 1) * (h + 1));
        let mut tris = Vec::with_capacity(n * 2 * h * h);
        for q in 0..n {
            let prev = (q + n - 1) % n;
            let base = out.len() as u32;
            for j in 0..=h {
                for i in 0..=h {
                    out.push(if j == 0 {
                        MeshSample::Fixed(self.piece_sample(&pc[q], i, m))
                    } else if i == 0 {
                        MeshSample::Fixed(self.piece_sample(&pc[prev], m - j, m))
                    } else if i == h {
                        spoke(q, j)
                    } else if j == h {
                        spoke(prev, i)
                    } else {
                        MeshSample::At(ngon_chart(
                            &dom,
                            q,
                            i as f64 / h as f64,
                            j as f64 / h as f64,
                        ))
                    });
                }
            }
            tris.extend(grid_triangles(h).iter().map(|t| t.map(|i| i + base)));
        }
        (out, tris)
    }

    /// Checks that an n-sided loop can be meshed (even resolution).
    pub(crate) fn check_ngon(&self, sides: usize) -> Result<(), StylingError> {
        if sides > 4 && !self.resolution.is_multiple_of(2) {
            return Err(StylingError::OddResolution(self.resolution));
        }
        Ok(())
    }
}
