//! Curve segments, knot-vector unions and bilinearly blended Coons patches
//! as one exact bicubic NURBS surface (moved here from the USD writer, issue
//! 15 item 5: geometry lives in the geometry floor, USD keeps the mapping).
//!
//! A Coons patch of four boundary curves plus a clamped uniform bicubic
//! displacement (paper 3 §5's patch form, `styling::network`):
//!
//! ```text
//! S(u,v) = (1-v) B(u) + v T(u) + (1-u) L(v) + u R(v) - bilinear(corners) + D(u,v)
//! ```
//!
//! Every term is a polynomial B-spline surface: the two ruled terms have
//! degree (3, 1) and (1, 3), the bilinear one (1, 1), the displacement
//! (3, 3). Each is degree-elevated to bicubic (exact, *The NURBS Book*
//! §5.5, through [`NurbsCurve::elevate_degree`]) and knot-refined (§5.3)
//! onto the union of all knot vectors, so the sum of the control nets is
//! the patch, exactly up to rounding. Boundary curves of lower degree are
//! elevated first; rational boundaries and degrees above 3 are refused
//! (they have no exact polynomial bicubic form).

use crate::math::DVec3;

use super::{
    clamped_uniform_knots, euclidean, homogeneous, knot_multiplicities, NurbsCurve, NurbsError,
    NurbsSurface,
};

/// The part of `c` over `[lo, hi]` (`lo < hi` inside the domain), as a
/// clamped curve over the same parameters (knot insertion to full
/// multiplicity at both ends, P&T §5.2).
pub fn segment(c: &NurbsCurve, lo: f64, hi: f64) -> Result<NurbsCurve, NurbsError> {
    let (a, b) = c.domain();
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(NurbsError::NonFinite("segment bounds"));
    }
    if !(a <= lo && lo < hi && hi <= b) {
        return Err(NurbsError::SegmentOutside { lo, hi, a, b });
    }
    let p = c.degree;
    let mut c = c.clone();
    for t in [lo, hi] {
        if t > a && t < b {
            c.insert_knot_to_multiplicity(t, p);
        }
    }
    let first = c.knots.iter().take_while(|&&k| k < lo).count().max(1) - 1;
    let inner: Vec<f64> = c
        .knots
        .iter()
        .copied()
        .filter(|&k| k > lo && k < hi)
        .collect();
    let mut knots = vec![lo; p + 1];
    knots.extend(&inner);
    knots.extend(std::iter::repeat_n(hi, p + 1));
    let n = knots.len() - p - 1;
    let control = c
        .control
        .get(first..first + n)
        .ok_or(NurbsError::BadKnots(
            "knot insertion left too few control points",
        ))?
        .to_vec();
    NurbsCurve::new(p, knots, control)
}

/// The union of knot vectors, each value with its largest multiplicity, in
/// increasing order.
pub fn knot_union(vectors: &[&[f64]]) -> Vec<f64> {
    let mut all: Vec<(f64, usize)> = Vec::new();
    for v in vectors {
        for (k, m) in knot_multiplicities(v) {
            match all.iter_mut().find(|(x, _)| *x == k) {
                Some(e) => e.1 = e.1.max(m),
                None => all.push((k, m)),
            }
        }
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    all.into_iter()
        .flat_map(|(k, m)| std::iter::repeat_n(k, m))
        .collect()
}

/// The four sides of a Coons patch on `[0, 1]²`, each a polynomial curve of
/// degree at most 3 over `[0, 1]`: `bottom` is `S(u, 0)`, `top` is `S(u, 1)`,
/// `left` is `S(0, v)`, `right` is `S(1, v)`. `corners` are `S(0,0)`,
/// `S(1,0)`, `S(0,1)`, `S(1,1)` (the sides' ends; a 3-sided patch has a
/// constant `left` side, its collapsed corner).
#[derive(Clone, Debug, PartialEq)]
pub struct CoonsSides {
    /// `S(u, 0)`.
    pub bottom: NurbsCurve,
    /// `S(1, v)`.
    pub right: NurbsCurve,
    /// `S(u, 1)`.
    pub top: NurbsCurve,
    /// `S(0, v)`.
    pub left: NurbsCurve,
    /// `[S(0,0), S(1,0), S(0,1), S(1,1)]`.
    pub corners: [DVec3; 4],
}

/// A control grid `points[i][j]` (`i` along `u`) with its degrees and knots.
struct Grid {
    degree: [usize; 2],
    knots: [Vec<f64>; 2],
    points: Vec<Vec<DVec3>>,
}

/// The control points of the polynomial curve with control points `pts`,
/// `degree` and `knots`, raised to degree 3 and refined to `target`.
fn to_cubic(
    pts: &[DVec3],
    degree: usize,
    knots: &[f64],
    target: &[f64],
) -> Result<Vec<DVec3>, NurbsError> {
    let control = pts.iter().map(|p| homogeneous(*p, 1.0)).collect();
    let c = NurbsCurve::new(degree, knots.to_vec(), control)?;
    Ok(cubic_on(&c, target)?
        .control
        .iter()
        .map(|h| euclidean(*h))
        .collect())
}

/// `c` as a cubic refined to `target` (refused when rational or above cubic).
fn cubic_on(c: &NurbsCurve, target: &[f64]) -> Result<NurbsCurve, NurbsError> {
    if c.degree > 3 {
        return Err(NurbsError::NotBicubic("a side has degree above 3"));
    }
    if c.control.iter().any(|h| h.w != 1.0) {
        return Err(NurbsError::NotBicubic("a side is rational"));
    }
    let mut c = if c.degree < 3 {
        c.elevate_degree(3 - c.degree)
    } else {
        c.clone()
    };
    c.refine_to(target);
    Ok(c)
}

impl Grid {
    /// The same surface as a bicubic grid on the knot vectors `ku`, `kv`.
    fn bicubic(&self, ku: &[f64], kv: &[f64]) -> Result<Vec<Vec<DVec3>>, NurbsError> {
        let columns = self
            .points
            .iter()
            .map(|col| to_cubic(col, self.degree[1], &self.knots[1], kv))
            .collect::<Result<Vec<_>, _>>()?;
        let n_v = columns.first().map_or(0, Vec::len);
        if columns.iter().any(|c| c.len() != n_v) {
            return Err(NurbsError::NotBicubic(
                "columns refined to different lengths",
            ));
        }
        let rows = (0..n_v)
            .map(|j| {
                let row: Vec<DVec3> = columns.iter().filter_map(|c| c.get(j).copied()).collect();
                to_cubic(&row, self.degree[0], &self.knots[0], ku)
            })
            .collect::<Result<Vec<_>, _>>()?;
        // Back to `[i][j]`.
        let n_u = rows.first().map_or(0, Vec::len);
        Ok((0..n_u)
            .map(|i| rows.iter().filter_map(|r| r.get(i).copied()).collect())
            .collect())
    }
}

const LINEAR: [f64; 4] = [0.0, 0.0, 1.0, 1.0];

/// The Coons patch of `sides` plus the displacement `disp` (an `n × n`
/// clamped uniform bicubic control grid on `[0, 1]²`, `disp[i * n + j]`
/// with `i` along `u`; `n >= 4`) as one polynomial bicubic NURBS surface on
/// `[0, 1]²`.
pub fn coons_bicubic(
    sides: &CoonsSides,
    disp: &[DVec3],
    n: usize,
) -> Result<NurbsSurface, NurbsError> {
    if n < 4 || disp.len() != n * n {
        return Err(NurbsError::DisplacementGrid {
            n,
            points: disp.len(),
        });
    }
    for c in [&sides.bottom, &sides.right, &sides.top, &sides.left] {
        if c.domain() != (0.0, 1.0) {
            return Err(NurbsError::NotBicubic(
                "a side is not parameterized on [0, 1]",
            ));
        }
    }
    let [p00, p10, p01, p11] = sides.corners;
    // Every side as a cubic first, then the same knots on opposite sides
    // of each ruled term.
    let [bottom, right, top, left] =
        [&sides.bottom, &sides.right, &sides.top, &sides.left].map(|c| cubic_on(c, &[]));
    let (bottom, right, top, left) = (bottom?, right?, top?, left?);
    let ku = knot_union(&[&bottom.knots, &top.knots]);
    let kv = knot_union(&[&left.knots, &right.knots]);
    let pts = |c: &NurbsCurve, target: &[f64]| -> Result<Vec<DVec3>, NurbsError> {
        Ok(cubic_on(c, target)?
            .control
            .iter()
            .map(|h| euclidean(*h))
            .collect())
    };
    let (b, t) = (pts(&bottom, &ku)?, pts(&top, &ku)?);
    let (l, r) = (pts(&left, &kv)?, pts(&right, &kv)?);
    let disp_knots = clamped_uniform_knots(n, 3);
    let terms = [
        // (1-v) B(u) + v T(u)
        (
            1.0,
            Grid {
                degree: [3, 1],
                knots: [ku.clone(), LINEAR.to_vec()],
                points: b.iter().zip(&t).map(|(b, t)| vec![*b, *t]).collect(),
            },
        ),
        // (1-u) L(v) + u R(v)
        (
            1.0,
            Grid {
                degree: [1, 3],
                knots: [LINEAR.to_vec(), kv.clone()],
                points: vec![l, r],
            },
        ),
        (
            -1.0,
            Grid {
                degree: [1, 1],
                knots: [LINEAR.to_vec(), LINEAR.to_vec()],
                points: vec![vec![p00, p01], vec![p10, p11]],
            },
        ),
        (
            1.0,
            Grid {
                degree: [3, 3],
                knots: [disp_knots.clone(), disp_knots.clone()],
                points: disp.chunks(n).map(<[DVec3]>::to_vec).collect(),
            },
        ),
    ];
    let ku_all = knot_union(&[&ku, &disp_knots]);
    let kv_all = knot_union(&[&kv, &disp_knots]);
    let mut sum: Vec<Vec<DVec3>> = Vec::new();
    for (sign, g) in &terms {
        let grid = g.bicubic(&ku_all, &kv_all)?;
        if sum.is_empty() {
            sum = grid
                .iter()
                .map(|row| vec![DVec3::ZERO; row.len()])
                .collect();
        }
        let same_shape =
            grid.len() == sum.len() && grid.iter().zip(&sum).all(|(a, b)| a.len() == b.len());
        if !same_shape {
            return Err(NurbsError::NotBicubic(
                "terms refined to different control nets",
            ));
        }
        for (srow, nrow) in sum.iter_mut().zip(&grid) {
            for (s, q) in srow.iter_mut().zip(nrow) {
                *s += *q * *sign;
            }
        }
    }
    let n_u = sum.len();
    let n_v = sum.first().map_or(0, Vec::len);
    let control = sum.iter().flatten().map(|p| homogeneous(*p, 1.0)).collect();
    NurbsSurface::new(3, 3, ku_all, kv_all, n_u, n_v, control)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(a: DVec3, b: DVec3) -> NurbsCurve {
        NurbsCurve::from_points(1, vec![0.0, 0.0, 1.0, 1.0], &[a, b]).unwrap()
    }

    fn arc(a: DVec3, b: DVec3, bulge: DVec3) -> NurbsCurve {
        let m = (a + b) * 0.5 + bulge;
        NurbsCurve::from_points(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0], &[a, m, b]).unwrap()
    }

    #[test]
    fn segment_matches_the_curve_and_refuses_outside() {
        let c = NurbsCurve::from_points(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0],
            &[
                DVec3::ZERO,
                DVec3::new(1.0, 2.0, 0.0),
                DVec3::new(2.0, -1.0, 1.0),
                DVec3::new(3.0, 0.5, 0.0),
                DVec3::new(4.0, 0.0, 2.0),
            ],
        )
        .unwrap();
        let s = segment(&c, 0.2, 0.7).unwrap();
        assert_eq!(s.domain(), (0.2, 0.7));
        for i in 0..=20 {
            let t = 0.2 + 0.5 * f64::from(i) / 20.0;
            assert!((s.point(t) - c.point(t)).length() < 1e-12);
        }
        assert!(matches!(
            segment(&c, 0.5, 1.5),
            Err(NurbsError::SegmentOutside { .. })
        ));
        assert!(matches!(
            segment(&c, 0.5, 0.5),
            Err(NurbsError::SegmentOutside { .. })
        ));
        assert!(matches!(
            segment(&c, f64::NAN, 0.5),
            Err(NurbsError::NonFinite(_))
        ));
    }

    #[test]
    fn knot_union_keeps_largest_multiplicity() {
        let u = knot_union(&[&[0.0, 0.0, 0.5, 1.0, 1.0], &[0.0, 0.5, 0.5, 0.7, 1.0]]);
        assert_eq!(u, vec![0.0, 0.0, 0.5, 0.5, 0.7, 1.0, 1.0]);
    }

    #[test]
    fn coons_surface_interpolates_sides_and_matches_the_blend() {
        let (p00, p10, p01, p11) = (
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.2),
            DVec3::new(1.0, 1.0, 0.0),
        );
        let sides = CoonsSides {
            bottom: arc(p00, p10, DVec3::new(0.0, -0.2, 0.1)),
            right: line(p10, p11),
            top: arc(p01, p11, DVec3::new(0.0, 0.1, 0.3)),
            left: arc(p00, p01, DVec3::new(-0.3, 0.0, 0.0)),
            corners: [p00, p10, p01, p11],
        };
        let n = 5;
        let mut disp = vec![DVec3::ZERO; n * n];
        disp[2 * n + 2] = DVec3::new(0.0, 0.0, 0.25);
        let s = coons_bicubic(&sides, &disp, n).unwrap();
        let dk = clamped_uniform_knots(n, 3);
        let d = NurbsSurface::new(
            3,
            3,
            dk.clone(),
            dk,
            n,
            n,
            disp.iter().map(|p| homogeneous(*p, 1.0)).collect(),
        )
        .unwrap();
        for i in 0..=10 {
            for j in 0..=10 {
                let (u, v) = (f64::from(i) / 10.0, f64::from(j) / 10.0);
                let want = (1.0 - v) * sides.bottom.point(u)
                    + v * sides.top.point(u)
                    + (1.0 - u) * sides.left.point(v)
                    + u * sides.right.point(v)
                    - ((1.0 - u) * (1.0 - v) * p00
                        + u * (1.0 - v) * p10
                        + (1.0 - u) * v * p01
                        + u * v * p11)
                    + d.point(u, v);
                assert!((s.point(u, v) - want).length() < 1e-12, "({u}, {v})");
            }
        }
        assert!(matches!(
            coons_bicubic(&sides, &disp[1..], n),
            Err(NurbsError::DisplacementGrid { .. })
        ));
    }
}
