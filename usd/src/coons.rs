//! Styling patches as exact NURBS surfaces, for their `NurbsPatch` prims.
//!
//! A patch of a curve network (paper 3 §5, `core::styling::network`) is a
//! bilinearly blended Coons patch of its 3 or 4 boundary pieces plus a
//! clamped uniform bicubic displacement:
//!
//! ```text
//! S(u,v) = (1-v) B(u) + v T(u) + (1-u) L(v) + u R(v) - bilinear(corners) + D(u,v)
//! ```
//!
//! Every term is a polynomial B-spline surface: the two ruled terms have
//! degree (3, 1) and (1, 3), the bilinear one (1, 1), the displacement
//! (3, 3). Each is degree-elevated to bicubic (linear Bézier directions
//! only) and knot-refined onto the union of all knot vectors, so the sum of
//! the control nets is the patch, exactly up to rounding. The pieces are
//! cut out of their curves by knot insertion and reparameterized onto
//! `[0, 1]`; a 3-sided patch has a constant left side (its collapsed node).
//! Conversion is done here, not in `core::styling`, because only the USD
//! export needs a patch as one NURBS surface; the styling tools work on the
//! displacement directly.

use shapewright::math::DVec3;
use shapewright::nurbs::{
    clamped_uniform_knots, euclidean, homogeneous, knot_multiplicities, NurbsCurve, NurbsSurface,
};
use shapewright::styling::{CurveNetwork, Piece};

/// The part of `c` over `[lo, hi]` (`lo < hi` inside the domain), as a
/// clamped curve over the same parameters.
pub fn segment(c: &NurbsCurve, lo: f64, hi: f64) -> Result<NurbsCurve, String> {
    let (a, b) = c.domain();
    if !(a <= lo && lo < hi && hi <= b) {
        return Err(format!(
            "segment [{lo}, {hi}] is not inside the domain [{a}, {b}]"
        ));
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
        .ok_or_else(|| "knot insertion left too few control points".to_owned())?
        .to_vec();
    NurbsCurve::new(p, knots, control).map_err(|e| e.to_string())
}

/// The piece as a curve on `[0, 1]`, from its `from` node to its `to` node.
fn piece_curve(net: &CurveNetwork, piece: &Piece) -> Result<NurbsCurve, String> {
    let curve = net
        .curve(piece.curve)
        .map_err(|e| e.to_string())?
        .to_nurbs()
        .map_err(|e| e.to_string())?;
    let param = |k: usize| {
        net.param(k, piece.curve)
            .ok_or_else(|| format!("node {k} is not on curve {}", piece.curve))
    };
    let (ta, tb) = (param(piece.from)?, param(piece.to)?);
    if ta == tb {
        return Err(format!("piece of curve {} has zero length", piece.curve));
    }
    Ok(if ta < tb {
        segment(&curve, ta, tb)?.with_domain(0.0, 1.0)
    } else {
        segment(&curve, tb, ta)?.with_domain(0.0, 1.0).reversed()
    })
}

/// A control grid `grid[i][j]` (`i` along `u`) with its degrees and knots.
struct Grid {
    degree: [usize; 2],
    knots: [Vec<f64>; 2],
    points: Vec<Vec<DVec3>>,
}

/// The control points of the curve with control points `pts`, `degree`
/// and `knots`, raised to degree 3 and refined to the knots `target`.
fn to_cubic(pts: &[DVec3], degree: usize, knots: &[f64], target: &[f64]) -> Vec<DVec3> {
    let control = pts.iter().map(|p| homogeneous(*p, 1.0)).collect();
    let mut c = NurbsCurve {
        degree,
        knots: knots.to_vec(),
        control,
    };
    if degree < 3 {
        c = c.elevate_degree(3 - degree);
    }
    c.refine_to(target);
    c.control.iter().map(|h| euclidean(*h)).collect()
}

impl Grid {
    /// The same surface as a bicubic grid on the knot vectors `ku`, `kv`.
    fn bicubic(&self, ku: &[f64], kv: &[f64]) -> Vec<Vec<DVec3>> {
        let columns: Vec<Vec<DVec3>> = self
            .points
            .iter()
            .map(|col| to_cubic(col, self.degree[1], &self.knots[1], kv))
            .collect();
        let n_v = columns.first().map_or(0, Vec::len);
        let rows: Vec<Vec<DVec3>> = (0..n_v)
            .map(|j| {
                let row: Vec<DVec3> = columns.iter().map(|c| c[j]).collect();
                to_cubic(&row, self.degree[0], &self.knots[0], ku)
            })
            .collect();
        // Back to `[i][j]`.
        let n_u = rows.first().map_or(0, Vec::len);
        (0..n_u)
            .map(|i| rows.iter().map(|r| r[i]).collect())
            .collect()
    }
}

/// The union of knot vectors, each value with its largest multiplicity.
fn knot_union(vectors: &[&[f64]]) -> Vec<f64> {
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

const LINEAR: [f64; 4] = [0.0, 0.0, 1.0, 1.0];

/// Patch `k` of `net` as one polynomial bicubic NURBS surface on `[0, 1]²`
/// (`S(u, v) = net.patch_point(k, u, v)` up to rounding).
pub fn patch_surface(net: &CurveNetwork, k: usize) -> Result<NurbsSurface, String> {
    let patch = net.patches.get(k).ok_or_else(|| format!("no patch {k}"))?;
    let pc = &patch.pieces;
    if !(pc.len() == 3 || pc.len() == 4) {
        return Err(format!("patch {k} has {} sides", pc.len()));
    }
    let n = net.surface_n as usize;
    if n < 4 || patch.disp.len() != n * n {
        return Err(format!(
            "patch {k} has {} displacement points for a {n}×{n} grid",
            patch.disp.len()
        ));
    }
    let bottom = piece_curve(net, &pc[0])?;
    let right = piece_curve(net, &pc[1])?;
    let top = piece_curve(net, &pc[2])?.reversed();
    let p00 = net.node_point(pc[0].from);
    let p10 = net.node_point(pc[1].from);
    let p11 = net.node_point(pc[2].from);
    let (left, p01) = if pc.len() == 4 {
        (
            piece_curve(net, &pc[3])?.reversed(),
            net.node_point(pc[3].from),
        )
    } else {
        let c = NurbsCurve::from_points(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], &[p00; 4])
            .map_err(|e| e.to_string())?;
        (c, p00)
    };
    // Same knots on opposite sides of each ruled term.
    let ku = knot_union(&[&bottom.knots, &top.knots]);
    let kv = knot_union(&[&left.knots, &right.knots]);
    let pts = |c: &NurbsCurve, target: &[f64]| to_cubic_h(c, target);
    let (b, t) = (pts(&bottom, &ku), pts(&top, &ku));
    let (l, r) = (pts(&left, &kv), pts(&right, &kv));
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
                points: (0..n)
                    .map(|i| {
                        (0..n)
                            .map(|j| DVec3::from_array(patch.disp[i * n + j]))
                            .collect()
                    })
                    .collect(),
            },
        ),
    ];
    let ku_all = knot_union(&[&ku, &disp_knots]);
    let kv_all = knot_union(&[&kv, &disp_knots]);
    let mut sum: Vec<Vec<DVec3>> = Vec::new();
    for (sign, g) in &terms {
        let grid = g.bicubic(&ku_all, &kv_all);
        if sum.is_empty() {
            sum = vec![vec![DVec3::ZERO; grid[0].len()]; grid.len()];
        }
        if grid.len() != sum.len() || grid[0].len() != sum[0].len() {
            return Err("terms refined to different control nets".to_owned());
        }
        for (srow, nrow) in sum.iter_mut().zip(&grid) {
            for (s, q) in srow.iter_mut().zip(nrow) {
                *s += *q * *sign;
            }
        }
    }
    let (n_u, n_v) = (sum.len(), sum[0].len());
    let control = sum.iter().flatten().map(|p| homogeneous(*p, 1.0)).collect();
    NurbsSurface::new(3, 3, ku_all, kv_all, n_u, n_v, control).map_err(|e| e.to_string())
}

/// The Euclidean control points of the cubic curve `c` refined to `target`.
fn to_cubic_h(c: &NurbsCurve, target: &[f64]) -> Vec<DVec3> {
    let mut c = c.clone();
    c.refine_to(target);
    c.control.iter().map(|h| euclidean(*h)).collect()
}
