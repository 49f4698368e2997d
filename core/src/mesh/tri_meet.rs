//! Exact predicates for two triangles of a self-intersection search
//! ([`super::self_intersections`]): do two closed triangles meet outside
//! the vertices they share, by what they share (nothing, a vertex, an
//! edge). Shewchuk's adaptive `orient3d` and `orient2d` (the `robust`
//! crate) decide every sign exactly; a float filter with Shewchuk's error
//! bound ([`Plane`]) settles almost every one of them in line, and four
//! points sharing a coordinate are settled as coplanar without the exact
//! stage. Exact for coordinates up to
//! [`MAX_EXACT_COORDINATE`](super::MAX_EXACT_COORDINATE) (the search does
//! not judge meshes beyond it).

use glam::DVec3;
use robust::{orient2d, orient3d, Coord, Coord3D};

fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

fn o3(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// `sign(orient3d(a, b, c, d))`, exactly, settled in line by the float
/// filter of [`Plane::side`] when it can be.
#[inline]
fn o3_sign(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> i8 {
    Plane::of([a, b, c]).side(d)
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Shewchuk's error bound for the first, floating-point stage of
/// `orient3d`: `(7 + 56ε)ε` with ε = 2⁻⁵³ ("Adaptive Precision
/// Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997,
/// §4.3; the `robust` crate's `o3derrboundA`).
const O3_ERR: f64 = (7.0 + 56.0 * (f64::EPSILON / 2.0)) * (f64::EPSILON / 2.0);

/// What underflow can add to that bound, which assumes none (as
/// Shewchuk's does). A 2×2 product of the plane's edge vectors that
/// underflows is off by up to 2⁻¹⁰⁷⁵ absolutely, not relatively, and is
/// then multiplied by a component of `q − a`, up to 2·[`MAX_EXACT_COORDINATE`](super::MAX_EXACT_COORDINATE):
/// six such products add at most 6 · 2⁻¹⁰⁷⁵ · 2e90 ≈ 3e-233, and the
/// later products' own underflow far less. A value within this of zero
/// goes to the adaptive predicate (the review of issue 37's change found
/// the plane (0, 2⁻⁵⁴⁰, 0), (1, 0, 0.75·2⁻⁵³⁵) through the origin and the
/// point (2²⁸⁰, 0, 2⁻²⁵⁶), whose sign a relative bound alone gets wrong).
const O3_ABS: f64 = 1e-220;

/// A triangle's plane, set up once per pair so that each side test is a
/// dot product: the sign of `orient3d(a, b, c, q)`, exact.
///
/// `orient3d(a, b, c, q) = (a − q)·((b − q) × (c − q)) = −(q − a)·((b − a) ×
/// (c − a))`, and the right-hand form has the structure Shewchuk's bound is
/// proved for (three differences of inputs, the 2×2 minors of two of them,
/// each times a component of the third, summed), so [`O3_ERR`] times its
/// permanent bounds its rounding error as it bounds `orient3d`'s first
/// stage, and [`O3_ABS`] what underflow adds. Only a test the float value cannot settle (a point on or within
/// rounding of the plane) runs the adaptive predicate; on a printable
/// mesh that is almost none (issue 37: `orient3d`'s call, with its cross
/// product recomputed for every point, was a quarter of the search).
struct Plane {
    t: [DVec3; 3],
    /// `(b − a) × (c − a)`, rounded.
    n: DVec3,
    /// The absolute 2×2 minors: `|u_y v_z| + |u_z v_y|`, …
    m: DVec3,
}

impl Plane {
    fn of(t: [DVec3; 3]) -> Self {
        let u = t[1] - t[0];
        let v = t[2] - t[0];
        Self {
            t,
            n: DVec3::new(
                u.y * v.z - u.z * v.y,
                u.z * v.x - u.x * v.z,
                u.x * v.y - u.y * v.x,
            ),
            m: DVec3::new(
                (u.y * v.z).abs() + (u.z * v.y).abs(),
                (u.z * v.x).abs() + (u.x * v.z).abs(),
                (u.x * v.y).abs() + (u.y * v.x).abs(),
            ),
        }
    }

    /// `sign(orient3d(a, b, c, q))`, exactly.
    #[inline]
    fn side(&self, q: DVec3) -> i8 {
        let w = q - self.t[0];
        let det = w.x * self.n.x + w.y * self.n.y + w.z * self.n.z;
        let perm = w.x.abs() * self.m.x + w.y.abs() * self.m.y + w.z.abs() * self.m.z;
        let bound = O3_ERR * perm + O3_ABS;
        if det > bound {
            return -1;
        }
        if -det > bound {
            return 1;
        }
        // Four points with one coordinate equal lie in that axis plane:
        // exactly zero, which the adaptive predicate reaches only through
        // its exact stage (a GC mesh's flat caps and rims: 58,484 such
        // calls in the teapot's search, every one of them zero).
        if (0..3).any(|k| self.t.iter().all(|p| p[k] == q[k])) {
            return 0;
        }
        sign(o3(self.t[0], self.t[1], self.t[2], q))
    }
}

/// Two triangles sharing the edge `e0 e1`, with other corners `c` and `d`,
/// overlap beyond the edge exactly when they are coplanar and on the same
/// side of it (folded flat onto each other).
pub(super) fn folded_onto(e0: DVec3, e1: DVec3, c: DVec3, d: DVec3) -> bool {
    if o3_sign(e0, e1, c, d) != 0 {
        return false;
    }
    let (u, v) = project_axes(e0, e1, c)
        .or_else(|| project_axes(e0, e1, d))
        .unwrap_or((0, 1));
    let s = |p: DVec3| sign(orient2d(c2(e0, u, v), c2(e1, u, v), c2(p, u, v)));
    let (sc, sd) = (s(c), s(d));
    // A degenerate triangle (its corner on the edge's line) overlaps the
    // other along the edge when that corner lies inside the edge.
    if sc == 0 || sd == 0 {
        let inside = |p: DVec3| {
            let t = (p - e0).dot(e1 - e0);
            t > 0.0 && t < (e1 - e0).length_squared()
        };
        return (sc == 0 && inside(c)) || (sd == 0 && inside(d));
    }
    sc == sd
}

/// Triangles `pa` and `pb` sharing exactly the corner `pa[i] == pb[j]`.
///
/// Their intersection is convex and holds the shared vertex `v`; if it holds
/// another point `q`, the ray from `v` through `q` leaves each triangle on
/// the edge opposite `v`, at `p1` and `p2`. The nearer of the two lies on
/// both triangles, so the opposite edge of one meets the other. Conversely
/// such a meeting point is not `v` (it lies on an edge not holding `v`).
pub(super) fn shares_vertex(pa: [DVec3; 3], i: usize, pb: [DVec3; 3], j: usize) -> bool {
    let (a1, a2) = (pa[(i + 1) % 3], pa[(i + 2) % 3]);
    let (b1, b2) = (pb[(j + 1) % 3], pb[(j + 2) % 3]);
    let (plane_a, plane_b) = (Plane::of(pa), Plane::of(pb));
    segment_meets_triangle(a1, a2, plane_b.side(a1), plane_b.side(a2), &plane_b)
        || segment_meets_triangle(b1, b2, plane_a.side(b1), plane_a.side(b2), &plane_a)
}

/// Closed triangles with no shared vertex meet exactly when one of the six
/// edges meets the other triangle (the intersection of two triangles, when
/// not empty, has a point on the boundary of one of them inside the other).
pub(super) fn triangles_meet(pa: [DVec3; 3], pb: [DVec3; 3]) -> bool {
    let (plane_a, plane_b) = (Plane::of(pa), Plane::of(pb));
    // Each corner's side of the other's plane, computed once.
    let sa = pa.map(|q| plane_b.side(q));
    let sb = pb.map(|q| plane_a.side(q));
    // Quick rejects: one triangle strictly on one side of the other's plane.
    let apart =
        |s: [i8; 3]| (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
    if apart(sa) || apart(sb) {
        return false;
    }
    (0..3).any(|k| {
        let l = (k + 1) % 3;
        segment_meets_triangle(pa[k], pa[l], sa[k], sa[l], &plane_b)
    }) || (0..3).any(|k| {
        let l = (k + 1) % 3;
        segment_meets_triangle(pb[k], pb[l], sb[k], sb[l], &plane_a)
    })
}

/// The closed segment `p q` meets the closed triangle of `plane`, given
/// the sides `sp`, `sq` of `p` and `q` ([`Plane::side`]).
fn segment_meets_triangle(p: DVec3, q: DVec3, sp: i8, sq: i8, plane: &Plane) -> bool {
    let t = plane.t;
    let [a, b, c] = t;
    if sp * sq > 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        return coplanar_segment_meets_triangle(p, q, t);
    }
    // The segment reaches the plane; its line passes through the closed
    // triangle exactly when the three edge orientations agree in sign.
    let s1 = o3_sign(p, q, a, b);
    let s2 = o3_sign(p, q, b, c);
    let s3 = o3_sign(p, q, c, a);
    let pos = s1 >= 0 && s2 >= 0 && s3 >= 0;
    let neg = s1 <= 0 && s2 <= 0 && s3 <= 0;
    if pos || neg {
        // All three zero: the triangle is degenerate and its line passes
        // through `p q`'s line; judge it as a segment.
        if s1 == 0 && s2 == 0 && s3 == 0 {
            return coplanar_segment_meets_triangle(p, q, t);
        }
        return true;
    }
    false
}

/// Two coordinates of the plane through three points in which they do not
/// project to a line, if any.
fn project_axes(a: DVec3, b: DVec3, c: DVec3) -> Option<(usize, usize)> {
    let n = (b - a).cross(c - a).abs();
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&x, &y| n[y].total_cmp(&n[x]));
    for drop in axes {
        let (u, v) = match drop {
            0 => (1, 2),
            1 => (2, 0),
            _ => (0, 1),
        };
        if orient2d(c2(a, u, v), c2(b, u, v), c2(c, u, v)) != 0.0 {
            return Some((u, v));
        }
    }
    None
}

fn c2(p: DVec3, u: usize, v: usize) -> Coord<f64> {
    Coord { x: p[u], y: p[v] }
}

/// Segment and triangle in one plane (or a degenerate triangle).
fn coplanar_segment_meets_triangle(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let [a, b, c] = t;
    let axes = project_axes(a, b, c)
        .or_else(|| project_axes(a, b, p))
        .or_else(|| project_axes(a, b, q))
        .or_else(|| project_axes(b, c, p))
        .or_else(|| project_axes(b, c, q))
        .or_else(|| project_axes(a, c, p))
        .or_else(|| project_axes(a, c, q));
    let Some((u, v)) = axes else {
        // Everything on one line: compare as 1D intervals.
        return collinear_overlap(p, q, t);
    };
    let o = |x: DVec3, y: DVec3, z: DVec3| sign(orient2d(c2(x, u, v), c2(y, u, v), c2(z, u, v)));
    let tri_area = o(a, b, c);
    if tri_area != 0 {
        let inside = |x: DVec3| {
            let (s1, s2, s3) = (o(a, b, x), o(b, c, x), o(c, a, x));
            (s1 * tri_area >= 0) && (s2 * tri_area >= 0) && (s3 * tri_area >= 0)
        };
        if inside(p) || inside(q) {
            return true;
        }
    }
    let seg_meet = |p1: DVec3, p2: DVec3, q1: DVec3, q2: DVec3| {
        let d1 = o(q1, q2, p1);
        let d2 = o(q1, q2, p2);
        let d3 = o(p1, p2, q1);
        let d4 = o(p1, p2, q2);
        if d1 * d2 < 0 && d3 * d4 < 0 {
            return true;
        }
        let on = |x: DVec3, y: DVec3, z: DVec3| {
            let (lo, hi) = (x.min(y), x.max(y));
            z[u] >= lo[u] && z[u] <= hi[u] && z[v] >= lo[v] && z[v] <= hi[v]
        };
        (d1 == 0 && on(q1, q2, p1))
            || (d2 == 0 && on(q1, q2, p2))
            || (d3 == 0 && on(p1, p2, q1))
            || (d4 == 0 && on(p1, p2, q2))
    };
    seg_meet(p, q, a, b) || seg_meet(p, q, b, c) || seg_meet(p, q, c, a)
}

/// All points on one line: the segment's interval meets the triangle's.
fn collinear_overlap(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let pts = [p, q, t[0], t[1], t[2]];
    let lo = pts
        .iter()
        .fold(DVec3::splat(f64::INFINITY), |a, b| a.min(*b));
    let hi = pts
        .iter()
        .fold(DVec3::splat(f64::NEG_INFINITY), |a, b| a.max(*b));
    let ext = hi - lo;
    let k = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let (s0, s1) = (p[k].min(q[k]), p[k].max(q[k]));
    let t0 = t[0][k].min(t[1][k]).min(t[2][k]);
    let t1 = t[0][k].max(t[1][k]).max(t[2][k]);
    s0 <= t1 && t0 <= s1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Found by the review of issue 37's change: a 2×2 product of the
    /// plane's edges underflows while the point is far away, and the
    /// relative bound alone trusted a float value of the wrong sign.
    #[test]
    fn an_underflowing_plane_is_judged_exactly() {
        let p2 = |e: i32| f64::from_bits(((1023 + e) as u64) << 52);
        let a = DVec3::ZERO;
        let b = DVec3::new(0.0, p2(-540), 0.0);
        let c = DVec3::new(1.0, 0.0, 0.75 * p2(-535));
        let q = DVec3::new(p2(280), 0.0, p2(-256));
        // −1.2e-240 in exact rational arithmetic; the float value of the
        // same expression is +2.4e-240 (one product of the plane's edges
        // rounds to zero).
        assert_eq!(sign(o3(a, b, c, q)), -1, "orient3d's own sign");
        assert_eq!(Plane::of([a, b, c]).side(q), -1);
    }

    proptest::proptest! {
        /// [`Plane::side`] is the exact sign of `orient3d`, also for a point
        /// within rounding of the plane, where the float value alone has
        /// the wrong sign about half the time.
        #[test]
        fn the_filtered_side_is_the_exact_sign(
            corners in proptest::array::uniform9(-1.0f64..1.0),
            s in -2.0f64..2.0,
            t in -2.0f64..2.0,
            lift in proptest::prop_oneof![proptest::strategy::Just(0.0), -1e-15f64..1e-15, -1.0f64..1.0],
            scale_exp in -20i32..20,
            far in proptest::prop_oneof![proptest::strategy::Just(0.0), -1.0f64..1.0],
        ) {
            let k = f64::from_bits(((1023 + scale_exp) as u64) << 52); // 2^scale_exp
            // Away from the origin (up to 2^20 times the triangle's size),
            // so the differences `b − a`, `q − a` round too.
            let c = corners.map(|x| x * k + far * k * 1048576.0);
            let (a, b, cc) = (
                DVec3::new(c[0], c[1], c[2]),
                DVec3::new(c[3], c[4], c[5]),
                DVec3::new(c[6], c[7], c[8]),
            );
            // A point on the plane up to the rounding of its coordinates,
            // lifted off it by `lift` of the triangle's size (or not).
            let n = (b - a).cross(cc - a).normalize_or_zero();
            let d = a + (b - a) * s + (cc - a) * t + n * (lift * k);
            let plane = Plane::of([a, b, cc]);
            proptest::prop_assert_eq!(plane.side(d), sign(o3(a, b, cc, d)));
            for q in [a, b, cc] {
                proptest::prop_assert_eq!(plane.side(q), 0);
            }
        }
    }

    proptest::proptest! {
        /// The axis-plane shortcut answers zero only for a point in the
        /// triangle's axis plane, and the exact sign one float off it.
        #[test]
        fn points_in_and_next_to_an_axis_plane_get_the_exact_sign(
            corners in proptest::array::uniform9(-1.0f64..1.0),
            axis in 0usize..3,
            level in proptest::prop_oneof![proptest::strategy::Just(0.0), -1.0f64..1.0, -1e-300f64..1e-300],
            off in -1i64..=1,
            scale_exp in -20i32..20,
        ) {
            let k = f64::from_bits(((1023 + scale_exp) as u64) << 52);
            let mut p: Vec<DVec3> = corners
                .chunks(3)
                .map(|c| DVec3::new(c[0], c[1], c[2]) * k)
                .collect();
            for q in &mut p {
                q[axis] = level;
            }
            // The fourth point in the plane, or one float above or below.
            let mut d = DVec3::new(corners[0] + corners[4], corners[8], corners[3]) * k;
            d[axis] = match off {
                0 => level,
                1 => level.next_up(),
                _ => level.next_down(),
            };
            let plane = Plane::of([p[0], p[1], p[2]]);
            proptest::prop_assert_eq!(plane.side(d), sign(o3(p[0], p[1], p[2], d)));
        }
    }
}
