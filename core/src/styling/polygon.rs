//! The parameter domain of an n-sided patch: a regular n-gon in the unit
//! square, with the distance, side-parameter, blending and weight
//! functions of the transfinite construction ([`super::ngon`]) and the
//! quadrature the surface tools integrate over it with.
//!
//! - Vertices `V_k = c + R (cos θ_k, sin θ_k)`, `c = (½, ½)`, `R = ½`,
//!   `θ_k = -π/2 - π/n + 2πk/n`: counter-clockwise, side 0 at the bottom
//!   running along `+x` (as a quad patch's `u` runs along its piece 0).
//!   Side `k` runs from `V_k` to `V_{k+1}`.
//! - `d_k(p)`: distance to the line of side `k` divided by the inradius, so
//!   `d_k = 0` on side `k` and `1` at the centre (affine in `p`).
//! - Side parameter `s_k = d_{k-1} / (d_{k-1} + d_{k+1})`: 0 at `V_k`, 1 at
//!   `V_{k+1}`, linear along side `k`, and `s_{k-1} = 1`, `s_{k+1} = 0` on
//!   side `k` (Várady, Rockwood, Salvi 2011, "Transfinite surface
//!   interpolation over irregular n-sided domains", corner-based patch).
//!   The denominator vanishes only where the lines of sides `k-1` and
//!   `k+1` meet, which lies outside the polygon for `n >= 4`.
//! - Side blends `μ_k = β_k / Σ β`, `β_k = Π_{j ≠ k} d_j²` (Kato's
//!   weights, `∝ 1 / d_k²`): 1 on side `k` and 0 there for every other
//!   side, with vanishing first derivative across the other sides. At a
//!   vertex `V_k` both `β_{k-1}` and `β_k` vanish and the blends depend on
//!   the direction the vertex is approached from: what lets the patch of
//!   [`super::ngon`] open a corner wider than the domain's (see there).
//! - Displacement weight `w = Π_k (1 + a) d_k / (d_k + a)` with `a = ¼`:
//!   smooth (C∞) on the closed polygon, 1 at the centre, zero on every side
//!   (linearly, about like the distance) and quadratically at the corners.
//!   A weight that behaved like the distance at a corner too (an R-function,
//!   or `1 / Σ 1/d_k`) would be a cone there, whose thin-plate energy
//!   diverges logarithmically; a plain product `Π d_k` is smooth but tiny
//!   near the sides for large `n` (`n² / 2^(n-1)` relative to the centre
//!   at a side's middle), which would ask for huge coefficients there.
//!
//! Quadrature: a B-spline cell inside the polygon gets the 4×4
//! Gauss-Legendre rule; a cell crossing a side is clipped to the polygon
//! (Sutherland-Hodgman) and each triangle of the clipped convex polygon
//! gets the 4×4 collapsed (Duffy) Gauss rule, exact for polynomials of
//! degree 6 on the triangle.

use crate::math::fm::DetMath as _;
use crate::math::DVec2;

use super::jet::Jet;

/// The 4-point Gauss-Legendre rule on `[0, 1]`: `(point, weight)`.
const GAUSS01: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_9, 0.326_072_577_431_273_06),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_06),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// The weight function's softness `a` (see the module doc).
const SOFT: f64 = 0.25;

/// A regular n-gon in the unit square (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct NgonDomain {
    verts: Vec<DVec2>,
    /// Outward unit normal of each side.
    out: Vec<DVec2>,
    inradius: f64,
}

impl NgonDomain {
    /// The regular `n`-gon (`n >= 3`; callers check the range).
    pub fn regular(n: usize) -> Self {
        let n = n.max(3);
        let c = DVec2::splat(0.5);
        let step = std::f64::consts::TAU / n as f64;
        let start = -std::f64::consts::FRAC_PI_2 - 0.5 * step;
        let verts = (0..n)
            .map(|k| {
                let t = start + step * k as f64;
                c + 0.5 * DVec2::new(t.fcos(), t.fsin())
            })
            .collect();
        let out = (0..n)
            .map(|k| {
                let t = -std::f64::consts::FRAC_PI_2 + step * k as f64;
                DVec2::new(t.fcos(), t.fsin())
            })
            .collect();
        Self {
            verts,
            out,
            inradius: 0.5 * (0.5 * step).fcos(),
        }
    }

    /// Number of sides.
    pub fn sides(&self) -> usize {
        self.verts.len()
    }

    /// Vertex `k` (start of side `k`).
    pub fn vertex(&self, k: usize) -> DVec2 {
        self.verts[k % self.sides()]
    }

    /// Middle of side `k`.
    pub fn mid(&self, k: usize) -> DVec2 {
        0.5 * (self.vertex(k) + self.vertex(k + 1))
    }

    /// The centre `(½, ½)`.
    pub fn centre(&self) -> DVec2 {
        DVec2::splat(0.5)
    }

    /// Normalized distance jets `d_k(p)` of every side.
    pub fn dists(&self, p: DVec2) -> Vec<Jet> {
        let c = self.centre();
        self.out
            .iter()
            .map(|u| {
                let g = -*u / self.inradius;
                Jet::affine(1.0 - (p - c).dot(*u) / self.inradius, g.x, g.y)
            })
            .collect()
    }

    /// The position jet of `p` along side `k`: its projection on the
    /// side's line, 0 at `V_k` and 1 at `V_{k+1}` (affine in `p`, and
    /// outside `[0, 1]` past the side's ends).
    pub fn along(&self, p: DVec2, k: usize) -> Jet {
        let (a, b) = (self.vertex(k), self.vertex(k + 1));
        let e = (b - a) / (b - a).length_squared();
        Jet::affine((p - a).dot(e), e.x, e.y)
    }

    /// Whether `p` lies in the closed polygon (to `tol` in normalized
    /// distance).
    pub fn contains(&self, p: DVec2, tol: f64) -> bool {
        self.dists(p).iter().all(|d| d.v >= -tol)
    }

    /// Side parameter jet `s_k` from the distance jets.
    pub fn side_param(d: &[Jet], k: usize) -> Jet {
        let n = d.len();
        let (a, b) = (d[(k + n - 1) % n], d[(k + 1) % n]);
        let den = a + b;
        if !(den.v.abs() > 1e-300) {
            return Jet::constant(0.5);
        }
        a * den.recip()
    }

    /// Side blend jets `μ_k = Π_{j≠k} d_j² / Σ_l Π_{j≠l} d_j²` (Kato's,
    /// `∝ 1 / d_k²`); they sum to 1, and on side `k` only `μ_k` is non-zero
    /// (it is 1 there). At a vertex, where two distances vanish, they
    /// depend on the direction it is approached from; exactly at one all
    /// the weight goes to the first nearest side.
    pub fn side_blends(d: &[Jet]) -> Vec<Jet> {
        let n = d.len();
        let sq: Vec<Jet> = d.iter().map(|x| *x * *x).collect();
        // Π_{j≠k} from prefix and suffix products, in a fixed order.
        let mut before = vec![Jet::constant(1.0); n + 1];
        for k in 0..n {
            before[k + 1] = before[k] * sq[k];
        }
        let mut after = vec![Jet::constant(1.0); n + 1];
        for k in (0..n).rev() {
            after[k] = after[k + 1] * sq[k];
        }
        let beta: Vec<Jet> = (0..n).map(|k| before[k] * after[k + 1]).collect();
        let sum = beta.iter().fold(Jet::constant(0.0), |acc, b| acc + *b);
        if !(sum.v > 0.0) {
            let mut out = vec![Jet::constant(0.0); n];
            let near = (0..n).fold(0, |m, k| if d[k].v < d[m].v { k } else { m });
            out[near] = Jet::constant(1.0);
            return out;
        }
        let inv = sum.recip();
        beta.into_iter().map(|b| b * inv).collect()
    }

    /// How far (in the domain) a unit of normalized distance reaches,
    /// in units of a side's length: the inradius over the side length.
    /// A ribbon `P(s) + d · c · (N × P')` with this `c` leaves each side
    /// at right angles and about as fast as it runs along it.
    pub fn ribbon_scale(&self) -> f64 {
        self.inradius / self.vertex(0).distance(self.vertex(1))
    }

    /// The displacement weight jet `w` (zero on every side).
    pub fn weight(d: &[Jet]) -> Jet {
        let a = SOFT;
        d.iter().fold(Jet::constant(1.0), |acc, x| {
            let den = x.v + a;
            let f = (1.0 + a) * x.v / den;
            let f1 = (1.0 + a) * a / (den * den);
            let f2 = -2.0 * (1.0 + a) * a / (den * den * den);
            acc * x.compose(f, f1, f2)
        })
    }

    /// The square `[x0, x1] × [y0, y1]` clipped to the polygon (a convex
    /// polygon, counter-clockwise; empty when they do not overlap).
    pub fn clip_rect(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<DVec2> {
        let mut poly = vec![
            DVec2::new(x0, y0),
            DVec2::new(x1, y0),
            DVec2::new(x1, y1),
            DVec2::new(x0, y1),
        ];
        let c = self.centre();
        for u in &self.out {
            if poly.is_empty() {
                break;
            }
            let f = |p: DVec2| self.inradius - (p - c).dot(*u);
            let mut next = Vec::with_capacity(poly.len() + 1);
            for i in 0..poly.len() {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                let (fa, fb) = (f(a), f(b));
                if fa >= 0.0 {
                    next.push(a);
                }
                if (fa >= 0.0) != (fb >= 0.0) {
                    next.push(a + (b - a) * (fa / (fa - fb)));
                }
            }
            poly = next;
        }
        poly
    }

    /// Quadrature points `(p, weight)` of the cell `[x0, x1] × [y0, y1]`
    /// intersected with the polygon.
    pub fn cell_quadrature(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<(DVec2, f64)> {
        let corners = [
            DVec2::new(x0, y0),
            DVec2::new(x1, y0),
            DVec2::new(x1, y1),
            DVec2::new(x0, y1),
        ];
        let mut out = Vec::new();
        if corners.iter().all(|p| self.contains(*p, 0.0)) {
            let (hx, hy) = (x1 - x0, y1 - y0);
            for (a, wa) in GAUSS01 {
                for (b, wb) in GAUSS01 {
                    out.push((DVec2::new(x0 + hx * a, y0 + hy * b), hx * hy * wa * wb));
                }
            }
            return out;
        }
        let poly = self.clip_rect(x0, x1, y0, y1);
        for i in 1..poly.len().saturating_sub(1) {
            let (a, b, c) = (poly[0], poly[i], poly[i + 1]);
            let area2 = (b - a).perp_dot(c - a);
            if !(area2 > 1e-300) {
                continue;
            }
            // Duffy: p = a + u (b - a) + u v (c - b), dA = area2 u du dv.
            for (u, wu) in GAUSS01 {
                for (v, wv) in GAUSS01 {
                    let p = a + (b - a) * u + (c - b) * (u * v);
                    out.push((p, area2 * u * wu * wv));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_params_and_blends_interpolate_the_sides() {
        for n in [3usize, 5, 6, 8, 12, 16] {
            let dom = NgonDomain::regular(n);
            let c = dom.dists(dom.centre());
            assert!(c.iter().all(|d| (d.v - 1.0).abs() < 1e-12));
            for k in 0..n {
                for i in 1..10 {
                    let t = i as f64 / 10.0;
                    let p = dom.vertex(k).lerp(dom.vertex(k + 1), t);
                    let d = dom.dists(p);
                    assert!(d[k].v.abs() < 1e-12);
                    assert!(NgonDomain::weight(&d).v.abs() < 1e-12);
                    if n >= 4 {
                        assert!((NgonDomain::side_param(&d, k).v - t).abs() < 1e-12);
                        assert!(NgonDomain::side_param(&d, (k + 1) % n).v.abs() < 1e-12);
                        let prev = NgonDomain::side_param(&d, (k + n - 1) % n).v;
                        assert!((prev - 1.0).abs() < 1e-12);
                    }
                    let b = NgonDomain::side_blends(&d);
                    let sum: f64 = b.iter().map(|x| x.v).sum();
                    assert!((sum - 1.0).abs() < 1e-12);
                    assert!((b[k].v - 1.0).abs() < 1e-12, "n {n} side {k}: {}", b[k].v);
                    for (j, bj) in b.iter().enumerate() {
                        if j != k {
                            assert!(bj.v.abs() < 1e-12, "n {n} side {k} side {j}: {}", bj.v);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn quadrature_integrates_the_polygon_area_and_moments() {
        for n in [5usize, 7, 12] {
            let dom = NgonDomain::regular(n);
            let cells = 9;
            let h = 1.0 / cells as f64;
            let (mut area, mut mx, mut mxx) = (0.0, 0.0, 0.0);
            for i in 0..cells {
                for j in 0..cells {
                    let (x0, y0) = (i as f64 * h, j as f64 * h);
                    for (p, w) in dom.cell_quadrature(x0, x0 + h, y0, y0 + h) {
                        area += w;
                        mx += w * p.x;
                        mxx += w * (p.x - 0.5) * (p.x - 0.5);
                    }
                }
            }
            let r = 0.5;
            let exact = 0.5 * n as f64 * r * r * (std::f64::consts::TAU / n as f64).fsin();
            assert!((area - exact).abs() < 1e-12, "n {n}: {area} vs {exact}");
            assert!((mx - 0.5 * exact).abs() < 1e-12);
            // Second moment of a regular polygon about a centroidal axis:
            // (A R² / 24) (2 + cos(2π/n)) ... in the form A/24 (6R² - a²)
            // with side a = 2 R sin(π/n).
            let a = 2.0 * r * (std::f64::consts::PI / n as f64).fsin();
            let ixx = exact / 24.0 * (6.0 * r * r - a * a);
            assert!((mxx - ixx).abs() < 1e-12, "n {n}: {mxx} vs {ixx}");
        }
    }
}
