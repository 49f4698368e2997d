//! Weaving curves into a network and keeping it connected (paper §5.1).
//!
//! - A new curve is tested against every curve of the net: local minima of
//!   the distance between dense samples of both, refined by alternating
//!   closest-point projection, below `snap_tol` are intersections. Hits
//!   near an existing node join it (so three curves meet at a box corner).
//!   The new curve is then re-approximated to interpolate the intersection
//!   points by the least change of its control points under a smoothing
//!   kernel (`d = K N (Nᵀ K N)⁻¹ δ`, `K_ij = exp(-((i-j)/3)²)`), which
//!   keeps its drawn shape and interpolates exactly.
//! - When a curve changes, every neighbour sharing a node with it follows
//!   by the same least-change solve, with its other nodes held, so shared
//!   points stay equal to rounding (tests check 1e-9).

use crate::math::fm::DetMath as _;
use crate::math::DVec3;

use super::curve::SplineCurve;
use super::network::{CurveNetwork, Node};
use super::StylingError;

/// One intersection found for a new curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Parameter on the new curve.
    pub t_new: f64,
    /// The existing curve.
    pub curve: usize,
    /// Parameter on it.
    pub t: f64,
    /// Distance at closest approach.
    pub dist: f64,
}

/// Where an intersection of a new curve goes: an existing node, or a new
/// node at `(curve, t)` of an existing curve.
type Target = Result<usize, (usize, f64)>;

/// Least change of `curve`'s control points so that `curve(t_k) = x_k`.
pub fn constrain(
    curve: &SplineCurve,
    index: usize,
    cons: &[(f64, DVec3)],
) -> Result<SplineCurve, StylingError> {
    let mut c = curve.clone();
    if cons.is_empty() {
        return Ok(c);
    }
    let n = c.n();
    let m = cons.len();
    let k = |i: usize, j: usize| {
        let d = (i as f64 - j as f64) / 3.0;
        (-d * d).fexp()
    };
    // Two passes: the second removes the rounding left by the first.
    for _ in 0..2 {
        let basis: Vec<(usize, Vec<f64>)> = cons.iter().map(|(t, _)| c.basis(*t)).collect();
        // K N, n × m.
        let mut kn = vec![0.0; n * m];
        for (col, (first, b)) in basis.iter().enumerate() {
            for i in 0..n {
                kn[i * m + col] = b.iter().enumerate().map(|(a, w)| k(i, first + a) * w).sum();
            }
        }
        let mut ntkn = vec![0.0; m * m];
        for (row, (first, b)) in basis.iter().enumerate() {
            for col in 0..m {
                ntkn[row * m + col] = b
                    .iter()
                    .enumerate()
                    .map(|(a, w)| w * kn[(first + a) * m + col])
                    .sum();
            }
        }
        let delta: Vec<DVec3> = cons.iter().map(|(t, x)| *x - c.point(*t)).collect();
        let lambda = crate::nurbs::solve(ntkn, delta)
            .map_err(|_| StylingError::DegenerateJunctions(index))?;
        for i in 0..n {
            let d: DVec3 = (0..m).map(|col| lambda[col] * kn[i * m + col]).sum();
            let p = DVec3::from_array(c.ctrl[i]) + d;
            c.ctrl[i] = p.to_array();
        }
    }
    let worst = cons
        .iter()
        .map(|(t, x)| c.point(*t).distance(*x))
        .fold(0.0, f64::max);
    if !(worst < 1e-10) || c.ctrl.iter().flatten().any(|v| !v.is_finite()) {
        return Err(StylingError::DegenerateJunctions(index));
    }
    Ok(c)
}

/// Closest approaches under `tol` between a new curve and `other`.
pub fn closest_approaches(
    new: &SplineCurve,
    other: &SplineCurve,
    tol: f64,
) -> Vec<(f64, f64, f64)> {
    let m1 = 12 * new.n();
    let m2 = 12 * other.n();
    let (a1, b1) = new.domain();
    let (a2, b2) = other.domain();
    let p1: Vec<(f64, DVec3)> = (0..=m1)
        .map(|i| {
            let t = a1 + (b1 - a1) * i as f64 / m1 as f64;
            (t, new.point(t))
        })
        .collect();
    let p2: Vec<(f64, DVec3)> = (0..=m2)
        .map(|i| {
            let t = a2 + (b2 - a2) * i as f64 / m2 as f64;
            (t, other.point(t))
        })
        .collect();
    let d = |i: usize, j: usize| p1[i].1.distance(p2[j].1);
    let mut out: Vec<(f64, f64, f64)> = Vec::new();
    let coarse = 4.0 * tol + 2.0 * ((b1 - a1) / m1 as f64).max((b2 - a2) / m2 as f64) * 0.0;
    // Blocks of samples whose bounding boxes are farther apart than the
    // threshold hold no candidate pair: skipping them keeps the search
    // near-linear in the samples (it visits the remaining pairs in the
    // same order, so the result is the same).
    let thr = coarse.max(tol * 4.0);
    let boxes = |p: &[(f64, DVec3)]| -> Vec<(DVec3, DVec3)> {
        p.chunks(BLOCK)
            .map(|c| {
                c.iter().fold((c[0].1, c[0].1), |(lo, hi), (_, q)| {
                    (lo.min(*q), hi.max(*q))
                })
            })
            .collect()
    };
    let (boxes1, boxes2) = (boxes(&p1), boxes(&p2));
    let near = |a: &(DVec3, DVec3), b: &(DVec3, DVec3)| {
        let gap = (a.0 - b.1).max(b.0 - a.1).max(DVec3::ZERO);
        !(gap.length() > thr * (1.0 + 1e-9))
    };
    for i in 0..=m1 {
        let bi = &boxes1[i / BLOCK];
        for (bj, box2) in boxes2.iter().enumerate() {
            if !near(bi, box2) {
                continue;
            }
            for j in bj * BLOCK..((bj + 1) * BLOCK).min(m2 + 1) {
                let dij = d(i, j);
                if dij > coarse.max(tol * 4.0) {
                    continue;
                }
                let mut local = true;
                'n: for di in -1i64..=1 {
                    for dj in -1i64..=1 {
                        let (ii, jj) = (i as i64 + di, j as i64 + dj);
                        if (di, dj) == (0, 0)
                            || ii < 0
                            || jj < 0
                            || ii > m1 as i64
                            || jj > m2 as i64
                        {
                            continue;
                        }
                        let o = d(ii as usize, jj as usize);
                        if o < dij || (o == dij && (di, dj) < (0, 0)) {
                            local = false;
                            break 'n;
                        }
                    }
                }
                if !local {
                    continue;
                }
                // Refine by alternating projection.
                let (mut t1, mut t2) = (p1[i].0, p2[j].0);
                for _ in 0..30 {
                    t2 = project(other, new.point(t1), t2);
                    t1 = project(new, other.point(t2), t1);
                }
                let dist = new.point(t1).distance(other.point(t2));
                if dist <= tol && !out.iter().any(|h| (h.0 - t1).abs() < 1e-6 * (b1 - a1)) {
                    out.push((t1, t2, dist));
                }
            }
        }
    }
    out
}

/// Samples per bounding box in [`closest_approaches`].
const BLOCK: usize = 16;

/// Newton projection of `p` onto `c` from `t`.
fn project(c: &SplineCurve, p: DVec3, mut t: f64) -> f64 {
    for _ in 0..8 {
        let d = c.derivs(t, 2);
        let f = (d[0] - p).dot(d[1]);
        let df = d[1].length_squared() + (d[0] - p).dot(d[2]);
        if !(df > 1e-300) {
            break;
        }
        t = c.clamp(t - f / df);
    }
    t
}

impl CurveNetwork {
    /// Adds a drawn curve: intersections with the net under `snap_tol`
    /// become nodes and the curve is re-approximated to interpolate them.
    /// Returns the new curve's index.
    pub fn add_curve(&mut self, curve: SplineCurve, snap_tol: f64) -> Result<usize, StylingError> {
        if !(snap_tol.is_finite() && snap_tol >= 0.0) {
            return Err(StylingError::BadParameter("snap_tol must be >= 0"));
        }
        let index = self.curves.len();
        // (t on new curve, node index or None + (curve, t) of a new node)
        let mut cons: Vec<(f64, Target)> = Vec::new();
        let (a, b) = curve.domain();
        for (ci, other) in self.curves.iter().enumerate() {
            let Some(other) = other else { continue };
            let (oa, ob) = other.domain();
            for (t_new, t, _) in closest_approaches(&curve, other, snap_tol) {
                let p = other.point(t);
                // Join an existing node of `other` close by.
                let near = self.nodes.iter().enumerate().find(|(_, n)| {
                    n.members.iter().any(|(c, tn)| {
                        *c == ci
                            && ((tn - t).abs() < 1e-3 * (ob - oa)
                                || other.point(*tn).distance(p) <= snap_tol)
                    })
                });
                let target = match near {
                    Some((k, _)) => Ok(k),
                    None => Err((ci, t)),
                };
                // Deduplicate hits on the new curve (a corner seen from two curves).
                let dup = cons.iter().any(|(tc, tg)| {
                    (tc - t_new).abs() < 1e-3 * (b - a)
                        || matches!((tg, &target), (Ok(x), Ok(y)) if x == y)
                });
                if !dup {
                    cons.push((t_new, target));
                }
            }
        }
        cons.sort_by(|x, y| x.0.total_cmp(&y.0));
        let targets: Vec<(f64, DVec3)> = cons
            .iter()
            .map(|(t, tg)| match tg {
                Ok(k) => (*t, self.node_point(*k)),
                Err((c, tc)) => (
                    *t,
                    self.curves[*c]
                        .as_ref()
                        .map(|cv| cv.point(*tc))
                        .unwrap_or(DVec3::NAN),
                ),
            })
            .collect();
        let fitted = constrain(&curve, index, &targets)?;
        self.curves.push(Some(fitted));
        for (t, tg) in cons {
            match tg {
                Ok(k) => self.nodes[k].members.push((index, t)),
                Err((c, tc)) => self.nodes.push(Node {
                    members: vec![(c, tc), (index, t)],
                }),
            }
        }
        Ok(index)
    }

    /// Replaces curve `i` (after a tool edit) and makes every neighbour
    /// follow so the net stays connected. On error the net is unchanged.
    pub fn set_curve(&mut self, i: usize, curve: SplineCurve) -> Result<(), StylingError> {
        self.curve(i)?;
        let old = self.curves[i].replace(curve);
        match self.followers(i) {
            Ok(moved) => {
                for (b, c) in moved {
                    self.curves[b] = Some(c);
                }
                Ok(())
            }
            Err(e) => {
                self.curves[i] = old;
                Err(e)
            }
        }
    }

    /// The neighbours of curve `i` moved to meet it at their shared nodes
    /// (their other nodes held).
    fn followers(&self, i: usize) -> Result<Vec<(usize, SplineCurve)>, StylingError> {
        let mut neighbours: Vec<usize> = self
            .nodes
            .iter()
            .filter(|n| n.members.iter().any(|(c, _)| *c == i))
            .flat_map(|n| n.members.iter().map(|(c, _)| *c))
            .filter(|c| *c != i)
            .collect();
        neighbours.sort_unstable();
        neighbours.dedup();
        let mut out = Vec::with_capacity(neighbours.len());
        for b in neighbours {
            let cb = self.curve(b)?.clone();
            let mut cons = Vec::new();
            for n in &self.nodes {
                let Some(&(_, tb)) = n.members.iter().find(|(c, _)| *c == b) else {
                    continue;
                };
                let target = match n.members.iter().find(|(c, _)| *c == i) {
                    Some((_, ti)) => self.curve(i)?.point(*ti),
                    None => cb.point(tb),
                };
                cons.push((tb, target));
            }
            out.push((b, constrain(&cb, b, &cons)?));
        }
        Ok(out)
    }

    /// Deletes curve `i`, its node memberships and the patches using it.
    pub fn delete_curve(&mut self, i: usize) -> Result<(), StylingError> {
        self.curve(i)?;
        self.curves[i] = None;
        for n in &mut self.nodes {
            n.members.retain(|(c, _)| *c != i);
        }
        self.patches
            .retain(|p| p.pieces.iter().all(|pc| pc.curve != i));
        Ok(())
    }
}
