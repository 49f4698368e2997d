//! Curve networks (paper §5): junctions, connectivity, loops and patches.
//!
//! A [`CurveNetwork`] holds curves (indices are never reused; a deleted
//! curve leaves `None`), nodes (junctions: the `(curve, t)` pairs that meet
//! there) and patches filling loops of curve pieces.
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
//! - Loops: pieces are the spans between consecutive nodes of a curve;
//!   automatic loops are the chordless cycles of 3 to 8 pieces (a
//!   topological criterion; the paper's geometric search is not specified
//!   further); explicit loops are checked to close. Filling them all goes
//!   by size (3- and 4-sided first, then 5, 6, ...) and skips a loop with
//!   a piece that already borders two patches, so on a closed net only the
//!   faces are filled (a cube's chordless hexagons are not).
//! - Patches: a bilinearly blended Coons patch of the 4 sides (a 3-sided
//!   loop is a Coons patch with one side collapsed to a point; loops of 5
//!   to 8 sides are split into quads around a centre, see [`super::ngon`]), plus a
//!   bicubic B-spline displacement with a zero boundary, edited by the
//!   surface tools. Patches are G0 to their curves by construction. Meshing
//!   samples each piece at canonical parameters and each node at one
//!   point, so neighbouring patches share boundary vertices bit for bit and
//!   a closed net welds into a closed 2-manifold.

use serde::{Deserialize, Serialize};

use crate::math::DVec3;
use crate::mesh::TriMesh;

use super::curve::SplineCurve;
use super::ngon::MAX_SIDES;
use super::surface::{eval_grid, BaseDerivs};
use super::StylingError;

/// A junction: the curve parameters that meet at one point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// `(curve index, parameter)` of each curve through this node.
    pub members: Vec<(usize, f64)>,
}

/// A span of one curve between two of its consecutive nodes, directed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Piece {
    /// Curve index.
    pub curve: usize,
    /// Start node.
    pub from: usize,
    /// End node.
    pub to: usize,
}

impl Piece {
    fn reversed(self) -> Self {
        Self {
            curve: self.curve,
            from: self.to,
            to: self.from,
        }
    }

    fn same_span(&self, o: &Piece) -> bool {
        self.curve == o.curve
            && ((self.from == o.from && self.to == o.to)
                || (self.from == o.to && self.to == o.from))
    }
}

/// A surface filling a loop.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Patch {
    /// The loop, 3 to 8 pieces head to tail.
    pub pieces: Vec<Piece>,
    /// Displacement control points (`n × n`, boundary zero; empty for
    /// loops of more than 4 pieces).
    pub disp: Vec<[f64; 3]>,
}

/// A network of styled curves with patches: the `CurveNetwork` object kind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveNetwork {
    /// Curves; `None` where a curve was deleted.
    pub curves: Vec<Option<SplineCurve>>,
    /// Junctions.
    pub nodes: Vec<Node>,
    /// Patches.
    pub patches: Vec<Patch>,
    /// Mesh samples per patch side.
    pub resolution: u32,
    /// Displacement control points per patch side.
    pub surface_n: u32,
}

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
        (-d * d).exp()
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
    for i in 0..=m1 {
        for j in 0..=m2 {
            let dij = d(i, j);
            if dij > coarse.max(tol * 4.0) {
                continue;
            }
            let mut local = true;
            'n: for di in -1i64..=1 {
                for dj in -1i64..=1 {
                    let (ii, jj) = (i as i64 + di, j as i64 + dj);
                    if (di, dj) == (0, 0) || ii < 0 || jj < 0 || ii > m1 as i64 || jj > m2 as i64 {
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
    out
}

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
    /// An empty network.
    pub fn new(resolution: u32, surface_n: u32) -> Result<Self, StylingError> {
        if !(2..=256).contains(&resolution) {
            return Err(StylingError::BadParameter("resolution must be 2..=256"));
        }
        if !(4..=64).contains(&surface_n) {
            return Err(StylingError::BadParameter("surface_n must be 4..=64"));
        }
        Ok(Self {
            curves: Vec::new(),
            nodes: Vec::new(),
            patches: Vec::new(),
            resolution,
            surface_n,
        })
    }

    /// The live curve `i`.
    pub fn curve(&self, i: usize) -> Result<&SplineCurve, StylingError> {
        self.curves
            .get(i)
            .and_then(|c| c.as_ref())
            .ok_or(StylingError::NoCurve(i))
    }

    /// The point of node `k` (its first member's evaluation).
    pub fn node_point(&self, k: usize) -> DVec3 {
        let (c, t) = self.nodes[k].members[0];
        self.curves[c]
            .as_ref()
            .map(|cv| cv.point(t))
            .unwrap_or(DVec3::NAN)
    }

    /// Parameter of node `k` on curve `c`.
    pub fn param(&self, k: usize, c: usize) -> Option<f64> {
        self.nodes
            .get(k)?
            .members
            .iter()
            .find(|(ci, _)| *ci == c)
            .map(|(_, t)| *t)
    }

    /// Largest distance between the members of any node.
    pub fn junction_gap(&self) -> f64 {
        let mut worst: f64 = 0.0;
        for n in &self.nodes {
            let pts: Vec<DVec3> = n
                .members
                .iter()
                .filter_map(|(c, t)| self.curves[*c].as_ref().map(|cv| cv.point(*t)))
                .collect();
            for p in &pts {
                worst = worst.max(p.distance(pts[0]));
            }
        }
        worst
    }

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

    /// Every piece: consecutive nodes along each live curve.
    pub fn pieces(&self) -> Vec<Piece> {
        let mut out = Vec::new();
        for (ci, c) in self.curves.iter().enumerate() {
            if c.is_none() {
                continue;
            }
            let mut on: Vec<(f64, usize)> = self
                .nodes
                .iter()
                .enumerate()
                .filter_map(|(k, n)| {
                    n.members
                        .iter()
                        .find(|(c, _)| *c == ci)
                        .map(|(_, t)| (*t, k))
                })
                .collect();
            on.sort_by(|a, b| a.0.total_cmp(&b.0));
            for w in on.windows(2) {
                out.push(Piece {
                    curve: ci,
                    from: w[0].1,
                    to: w[1].1,
                });
            }
        }
        out
    }

    /// Chordless loops of 3 to [`MAX_SIDES`] pieces not yet filled, each
    /// as pieces head to tail, in a deterministic order.
    pub fn find_loops(&self) -> Vec<Vec<Piece>> {
        let pieces = self.pieces();
        let connected = |a: usize, b: usize| {
            pieces
                .iter()
                .any(|p| (p.from == a && p.to == b) || (p.from == b && p.to == a))
        };
        let step = |p: &Piece, at: usize| -> Option<Piece> {
            if p.from == at {
                Some(*p)
            } else if p.to == at {
                Some(p.reversed())
            } else {
                None
            }
        };
        let mut found: Vec<(Vec<usize>, Vec<Piece>)> = Vec::new();
        for (e0, p0) in pieces.iter().enumerate() {
            let mut stack: Vec<(Vec<usize>, Vec<Piece>)> = vec![(vec![e0], vec![*p0])];
            while let Some((ids, path)) = stack.pop() {
                let last = path[path.len() - 1];
                let start = path[0].from;
                if path.len() >= 3 && last.to == start {
                    let nodes: Vec<usize> = path.iter().map(|p| p.from).collect();
                    let n = nodes.len();
                    let chord = (0..n).any(|i| {
                        (i + 2..n).any(|j| (j + 1) % n != i && connected(nodes[i], nodes[j]))
                    });
                    let mut key = ids.clone();
                    key.sort_unstable();
                    if !chord && !found.iter().any(|(k, _)| *k == key) {
                        found.push((key, path));
                    }
                    continue;
                }
                if path.len() == MAX_SIDES {
                    continue;
                }
                for (e, p) in pieces.iter().enumerate() {
                    if ids.contains(&e) || e < e0 {
                        continue;
                    }
                    let Some(next) = step(p, last.to) else {
                        continue;
                    };
                    let revisit = path.iter().any(|q| q.from == next.to) && next.to != start;
                    if revisit {
                        continue;
                    }
                    let mut ids2 = ids.clone();
                    ids2.push(e);
                    let mut path2 = path.clone();
                    path2.push(next);
                    stack.push((ids2, path2));
                }
            }
        }
        found
            .into_iter()
            .map(|(_, p)| p)
            .filter(|l| self.filled_by(l).is_none())
            .collect()
    }

    fn filled_by(&self, lp: &[Piece]) -> Option<usize> {
        self.patches.iter().position(|p| {
            p.pieces.len() == lp.len() && lp.iter().all(|a| p.pieces.iter().any(|b| a.same_span(b)))
        })
    }

    /// Checks that `lp` is a closed loop of 3 to [`MAX_SIDES`] pieces of
    /// live curves, each between consecutive nodes of its curve.
    pub fn check_loop(&self, lp: &[Piece]) -> Result<(), StylingError> {
        if lp.len() < 3 || lp.len() > MAX_SIDES {
            return Err(StylingError::LoopSize(lp.len()));
        }
        self.check_ngon(lp.len())?;
        let all = self.pieces();
        for (k, p) in lp.iter().enumerate() {
            self.curve(p.curve)?;
            if !all.iter().any(|q| q.same_span(p)) {
                return Err(StylingError::LoopNotClosed(format!(
                    "piece {k} (curve {}, nodes {} -> {}) is not a span between consecutive nodes of its curve",
                    p.curve, p.from, p.to
                )));
            }
            let next = lp[(k + 1) % lp.len()];
            if p.to != next.from {
                return Err(StylingError::LoopNotClosed(format!(
                    "piece {k} ends at node {} but piece {} starts at node {}",
                    p.to,
                    (k + 1) % lp.len(),
                    next.from
                )));
            }
        }
        let mut nodes: Vec<usize> = lp.iter().map(|p| p.from).collect();
        nodes.sort_unstable();
        nodes.dedup();
        if nodes.len() != lp.len() {
            return Err(StylingError::LoopNotClosed(
                "the loop visits a node twice".into(),
            ));
        }
        Ok(())
    }

    /// Fills a loop with a patch, oriented against the patches it borders.
    /// Returns the patch index.
    pub fn fill(&mut self, lp: &[Piece]) -> Result<usize, StylingError> {
        self.check_loop(lp)?;
        if let Some(k) = self.filled_by(lp) {
            return Err(StylingError::AlreadyFilled(k));
        }
        let mut pieces = lp.to_vec();
        let same_dir = self.patches.iter().flat_map(|p| &p.pieces).any(|q| {
            pieces
                .iter()
                .any(|p| p.curve == q.curve && p.from == q.from && p.to == q.to)
        });
        if same_dir {
            pieces = pieces.iter().rev().map(|p| p.reversed()).collect();
        }
        let n = if pieces.len() > 4 {
            0
        } else {
            self.surface_n as usize
        };
        self.patches.push(Patch {
            pieces,
            disp: vec![[0.0; 3]; n * n],
        });
        Ok(self.patches.len() - 1)
    }

    /// Patches bordering the span of `p`.
    fn borders(&self, p: &Piece) -> usize {
        self.patches
            .iter()
            .flat_map(|q| &q.pieces)
            .filter(|q| q.same_span(p))
            .count()
    }

    /// Fills every automatically found loop by size tiers (3 and 4 sides,
    /// then 5, 6, ...), neighbours first within a tier (each next loop
    /// shares a piece with a filled one when possible), so that the
    /// orientation propagates consistently over a closed net. A loop with
    /// a piece that already borders two patches is skipped.
    pub fn fill_all(&mut self) -> Result<Vec<usize>, StylingError> {
        let tier = |l: &Vec<Piece>| l.len().max(4);
        let mut loops = self.find_loops();
        loops.sort_by_key(tier);
        let mut out = Vec::new();
        while !loops.is_empty() {
            let now = tier(&loops[0]);
            let next = loops
                .iter()
                .position(|l| tier(l) == now && l.iter().any(|p| self.borders(p) > 0))
                .unwrap_or(0);
            let lp = loops.remove(next);
            if lp.iter().any(|p| self.borders(p) >= 2) {
                continue;
            }
            out.push(self.fill(&lp)?);
        }
        Ok(out)
    }

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

    /// Point of patch `k` at `(u, v)`: Coons base plus displacement.
    pub fn patch_point(&self, k: usize, u: f64, v: f64) -> DVec3 {
        let n = self.surface_n as usize;
        self.coons(k, u, v)[0] + eval_grid(n, n, &self.patches[k].disp, u, v)
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

    /// Triangle mesh of patch `k` (boundary vertices on the curves).
    pub fn patch_mesh(&self, k: usize) -> TriMesh {
        if self.patches[k].pieces.len() > 4 {
            return self.ngon_mesh(k);
        }
        let m = self.resolution as usize;
        let pc = &self.patches[k].pieces;
        let mut pos = Vec::with_capacity((m + 1) * (m + 1));
        for j in 0..=m {
            for i in 0..=m {
                let p = if j == 0 {
                    self.piece_sample(&pc[0], i, m)
                } else if i == m {
                    self.piece_sample(&pc[1], j, m)
                } else if j == m {
                    self.piece_sample(&pc[2], m - i, m)
                } else if i == 0 {
                    if pc.len() == 4 {
                        self.piece_sample(&pc[3], m - j, m)
                    } else {
                        self.node_point(pc[0].from)
                    }
                } else {
                    self.patch_point(k, i as f64 / m as f64, j as f64 / m as f64)
                };
                pos.push(p.to_array());
            }
        }
        TriMesh::new(pos, grid_triangles(m))
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
