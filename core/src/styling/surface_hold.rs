//! The surface tools held along a pointer path on a network's patch
//! (paper 3 §4; issue 33): where the path passes, how fast the patch may
//! change, and where a tool must stop.
//!
//! - **Where the path passes.** The paper's surface smoother and sharpener
//!   act on the whole surface (§4.1: "weighted energy functions are not
//!   implemented"); its curve tools act where the pointer is (§3, eq. 19).
//!   Given a `radius`, a held surface tool does the same: frame `k` with
//!   the pointer at `p_k` moves each displacement control point by the
//!   gaussian weight `γ = exp(-(|q - p_k| / radius)²)` of the distance from
//!   the patch point `q` at its Greville parameters (on the patch as it is
//!   at that frame), so dragging the pointer across the patch smooths or
//!   sharpens along the way and nowhere else. Without a radius every weight
//!   is 1: the paper's global tool, which only counts frames.
//! - **How it moves.** The energy matrix is factored once per activation
//!   (§4) for the minimal-energy displacement `d_min` with the patch's
//!   boundary; each control point keeps its own equilibrium weight `w_q`
//!   (eq. 22), which frame `k` multiplies by `1 + γ (f - 1)`, so a control
//!   point is at `d_min + w_q (d_0 - d_min)`: with `γ = 1` everywhere this
//!   is exactly the global tool's `w_q = f^k`. The sharpener's `w_q` is
//!   capped at `wq_max`. With `max_step`, a frame that would move any
//!   control point (and so, by the B-spline's convex hull, any point of
//!   the patch) farther than `max_step` is scaled down to it: the headset
//!   sends `max_step` so that one held second changes a patch by a few
//!   centimetres at most, at any frame rate up to 120 Hz.
//! - **Where it stops.** A frame that would make the patch overhang its
//!   boundary, or crease it tighter than a printed wall can follow, is
//!   taken only as far as it does not (the largest of its half, quarter
//!   and eighth) and the tool stops there (like the curve sharpener's
//!   limits, not an error: the frames before are kept), with the
//!   [`SurfaceStop`] that refused the last part tried. The puller stops
//!   the same way. Both are checked on the patch's mesh (what prints):
//!   - *Overhang*: a triangle that faced along the loop's normal at
//!     activation (the vector area of the boundary, which no tool
//!     changes) turns to face against it or collapses: the surface folds
//!     back over its boundary.
//!   - *Crease*: an interior edge's crease `h / tan(θ / 2)` (`θ` the angle
//!     between its two triangles' normals, `h` the smaller one's height
//!     over the edge) falls below the document's wall `t`
//!     (`set_wall_thickness`, 2 mm by default; or below the edge's crease
//!     at activation, when that was tighter). The wall is the one the
//!     document has when the op applies, so a replay stops where the live
//!     tool did; a wall thickened later is checked by the print, which
//!     refuses a shell that would pass through itself.
//!     Offsetting the two faces by `t` moves their meeting line
//!     `t tan(θ / 2)` into each face: past the opposite corner when the
//!     crease is below `t`, and the offset sheet turns over there. This is
//!     what the overhang check missed: once the side-based n-gon patch
//!     stopped folding in its plane, the strongest held sharpener (f = 2,
//!     `w_q` up to 100, global, unbounded steps) raised the 15 cm
//!     hexagon's 4.3 cm bump to 1.72 m (`w_q` about 40) before anything
//!     faced down, and its 2 mm shell passed through itself in 86 pairs.
//!     Measured on the bowed 6-, 7-, 12- and 16-gons with `w_q` swept from
//!     1 to 100 (steps of 10%): every shell that passed through itself
//!     (any offset) had a crease of 1.16 mm or less; every mesh with
//!     creases of 2.49 mm or more printed. The crease check stops the
//!     hexagon at `w_q` = 32 (1.38 m, creases 5.5 mm); the 12- and 16-gons
//!     are stopped earlier by the overhang. A height cap (rise against
//!     the loop's diameter) was the alternative: it does not see a narrow
//!     local spike of a pointer-held sharpener, which creases the mesh
//!     well below any height cap, and it would refuse tall shapes that
//!     print. The check is local, so it is cheap: one cross product per
//!     triangle and one per interior edge each frame (the edges, across
//!     the n-gon mesh's seams too, are found once at activation).
//!     The margin is for the default, centred shell (half the wall on each
//!     side): with the whole wall on one side (inward or outward shells),
//!     a pointer-held sharpener stopped at 2 mm creases can still leave a
//!     few shell pairs crossing: in a sweep of settings (f 1.05 to 2,
//!     `w_q` up to 100, radius none, 3 or 8 cm, `max_step` none or 2 mm,
//!     held still or dragged, on 5- to 16-gons) up to 86 for an inward
//!     2 mm shell, none for the centred one; a stop at twice the wall
//!     still left 7. The check sees only the patch's own edges, not the
//!     edges along its boundary curves to the neighbouring patches.
//!
//! The patch's mesh is evaluated once at activation as base points plus
//! displacement coefficients (`PatchSampler`), so a frame costs a sparse
//! product, not a re-evaluation of the (transfinite) base surface.

use crate::math::fm::DetMath as _;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

use crate::math::{DVec2, DVec3};

use super::budget::Budget;
use super::network::CurveNetwork;
use super::patch::MeshSample;
use super::polygon::NgonDomain;
use super::surface::{point_basis, SurfaceWeights};
use super::StylingError;

/// Why a held surface tool stopped before the end of its path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceStop {
    /// The next frame would have made the patch overhang its boundary.
    Overhang,
    /// The next frame would have creased the patch's mesh tighter than a
    /// printed wall can follow (its shell would pass through itself).
    Crease,
}

/// How a held smoother (`f < 1`) or sharpener (`f > 1`) acts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EquilibriumHold {
    /// Factor on each control point's `w_q` per frame (at full weight).
    pub f: f64,
    /// Cap on `w_q`.
    pub wq_max: f64,
    /// Gaussian radius of the pointer's reach (model units); `None`: the
    /// whole patch.
    pub radius: Option<f64>,
    /// Largest move of a control point in one frame (model units);
    /// `None`: unbounded.
    pub max_step: Option<f64>,
}

/// Points of a patch as fixed base points plus a linear function of its
/// displacement control points, evaluated once.
pub(crate) struct PatchSampler {
    base: Vec<DVec3>,
    /// Per point: first control index along `u` and `v` and the 4×4
    /// coefficients (none for boundary samples).
    rows: Vec<Option<(usize, usize, [f64; 16])>>,
    n: usize,
}

impl PatchSampler {
    /// The points `samples` of patch `k` of `net`.
    pub(crate) fn new(net: &CurveNetwork, k: usize, samples: &[MeshSample]) -> Self {
        let n = net.surface_n as usize;
        let sides = net.patches[k].pieces.len();
        let dom = (sides > 4).then(|| NgonDomain::regular(sides));
        let mut base = Vec::with_capacity(samples.len());
        let mut rows = Vec::with_capacity(samples.len());
        for s in samples {
            match *s {
                MeshSample::Fixed(p) => {
                    base.push(p);
                    rows.push(None);
                }
                MeshSample::At(uv) => {
                    let (b, w) = match &dom {
                        Some(d) => (
                            net.ngon_base(k, d, uv).v,
                            NgonDomain::weight(&d.dists(uv)).v,
                        ),
                        None => (net.coons(k, uv.x, uv.y)[0], 1.0),
                    };
                    let (fu, bu) = point_basis(n, uv.x);
                    let (fv, bv) = point_basis(n, uv.y);
                    let mut c = [0.0; 16];
                    for x in 0..4 {
                        for y in 0..4 {
                            c[x * 4 + y] = bu[x] * bv[y] * w;
                        }
                    }
                    base.push(b);
                    rows.push(Some((fu, fv, c)));
                }
            }
        }
        Self { base, rows, n }
    }

    /// The points with displacement control points `disp`.
    pub(crate) fn eval(&self, disp: &[[f64; 3]]) -> Vec<DVec3> {
        let n = self.n;
        self.base
            .iter()
            .zip(&self.rows)
            .map(|(b, row)| match row {
                None => *b,
                Some((fu, fv, c)) => {
                    let mut p = *b;
                    for x in 0..4 {
                        for y in 0..4 {
                            p += DVec3::from_array(disp[(fu + x) * n + fv + y]) * c[x * 4 + y];
                        }
                    }
                    p
                }
            })
            .collect()
    }
}

/// Watches a patch's mesh for an overhang over its boundary and for a
/// crease tighter than a printed wall (see the module doc).
pub(crate) struct SurfaceGuard {
    triangles: Vec<[u32; 3]>,
    /// Per triangle, the direction it must keep facing along (`None`: not
    /// watched, it did not face along the loop's normal at activation).
    facing: Vec<Option<DVec3>>,
    /// The interior edges: its two ends, its two triangles, and the
    /// tightest crease it may reach (the wall, or its own crease at
    /// activation if that was tighter already).
    edges: Vec<WatchedEdge>,
}

struct WatchedEdge {
    ends: [u32; 2],
    tris: [u32; 2],
    floor: f64,
}

/// A triangle faces along `dir` when its normal's component along `dir`
/// is above this fraction of its length (a margin for rounding: the
/// sampler's sums differ from the mesh's in the last bits).
const FACING_MARGIN: f64 = 1e-6;

fn normal_of(p: &[DVec3], t: &[u32; 3]) -> DVec3 {
    let [a, b, c] = t.map(|i| p[i as usize]);
    (b - a).cross(c - a)
}

/// The crease of an interior edge of length `len` between triangles with
/// (unnormalized) normals `a` and `b`: `h / tan(θ / 2)`, `h` the smaller
/// triangle's height over the edge and `θ` the angle between the normals.
/// A wall of thickness `t` offset to the concave side of the edge moves
/// the faces' meeting line `t tan(θ / 2)` into each face, past the
/// opposite corner once that exceeds `h`: the offset sheet turns over
/// there when the crease is below `t`. Infinite for a flat edge, zero for
/// a folded one (and NaN for a collapsed triangle, which no comparison
/// accepts).
fn crease(a: DVec3, b: DVec3, len: f64) -> f64 {
    let (la, lb, dot) = (a.length(), b.length(), a.dot(b));
    let sin = a.cross(b).length();
    if sin == 0.0 && dot > 0.0 {
        return f64::INFINITY;
    }
    // `1 / tan(θ / 2)` as `(|a||b| + a·b) / |a × b|`, or, for normals
    // turned more than a right angle (where that sum cancels), as the
    // equal `|a × b| / (|a||b| - a·b)`: zero, not infinite, for a fold.
    let cot = if dot >= 0.0 {
        (la * lb + dot) / sin
    } else {
        sin / (la * lb - dot)
    };
    la.min(lb) * cot / len
}

impl SurfaceGuard {
    /// Watches the mesh `points`/`triangles` as it is at activation;
    /// `samples` (where each point comes from) say which triangles meet
    /// across the seams of the patch's mesh.
    /// `wall` is the print's wall thickness.
    pub(crate) fn new(
        points: &[DVec3],
        triangles: Vec<[u32; 3]>,
        samples: &[MeshSample],
        wall: f64,
    ) -> Self {
        let normals: Vec<DVec3> = triangles.iter().map(|t| normal_of(points, t)).collect();
        let area: f64 = normals.iter().map(|n| n.length()).sum();
        // The vector area of a disk-like patch is its boundary's: the
        // loop's normal, which the tools never change.
        let loop_area = normals.iter().copied().sum::<DVec3>();
        let facing = if loop_area.length() > 1e-3 * area {
            let dir = loop_area.normalize();
            normals
                .iter()
                .map(|n| (n.dot(dir) > FACING_MARGIN * n.length()).then_some(dir))
                .collect()
        } else {
            // No loop direction (a saddle whose boundary encloses no net
            // area): each triangle keeps facing the way it did.
            normals.iter().map(|n| n.try_normalize()).collect()
        };
        let edges = interior_edges(&triangles, samples)
            .into_iter()
            .filter(|(_, [s, t])| {
                normals[*s as usize] != DVec3::ZERO && normals[*t as usize] != DVec3::ZERO
            })
            .filter_map(|(ends, tris)| {
                let len = points[ends[0] as usize].distance(points[ends[1] as usize]);
                let now = crease(normals[tris[0] as usize], normals[tris[1] as usize], len);
                // A fold already there at activation is not watched; an
                // edge already tighter than the wall may not get tighter
                // (by more than rounding).
                (!now.is_nan()).then_some(WatchedEdge {
                    ends,
                    tris,
                    floor: if now < wall { now * (1.0 - 1e-9) } else { wall },
                })
            })
            .collect();
        Self {
            triangles,
            facing,
            edges,
        }
    }

    /// Why the mesh `points` would stop a tool, if it would: a watched
    /// triangle no longer facing its way or collapsed (an overhang), or an
    /// interior edge creased tighter than it may be.
    pub(crate) fn check(&self, points: &[DVec3]) -> Option<SurfaceStop> {
        let normals: Vec<DVec3> = self
            .triangles
            .iter()
            .map(|t| normal_of(points, t))
            .collect();
        let faces = normals.iter().zip(&self.facing).all(|(n, dir)| {
            let Some(dir) = dir else { return true };
            let l = n.length();
            l.is_finite() && l > 0.0 && n.dot(*dir) > FACING_MARGIN * l
        });
        if !faces {
            return Some(SurfaceStop::Overhang);
        }
        let creased = self.edges.iter().any(|e| {
            let len = points[e.ends[0] as usize].distance(points[e.ends[1] as usize]);
            let c = crease(
                normals[e.tris[0] as usize],
                normals[e.tris[1] as usize],
                len,
            );
            !(c >= e.floor)
        });
        creased.then_some(SurfaceStop::Crease)
    }
}

/// The edges of `triangles` shared by exactly two of them, as their two
/// ends and two triangles; points are the same when their samples are
/// (an n-sided patch's mesh is one grid per corner, sharing its spokes
/// and boundary samples by value).
fn interior_edges(triangles: &[[u32; 3]], samples: &[MeshSample]) -> Vec<([u32; 2], [u32; 2])> {
    let key = |i: u32| match samples[i as usize] {
        MeshSample::Fixed(p) => (0u8, p.to_array().map(f64::to_bits)),
        MeshSample::At(uv) => (1u8, [uv.x.to_bits(), uv.y.to_bits(), 0]),
    };
    let mut ids: BTreeMap<(u8, [u64; 3]), u32> = BTreeMap::new();
    let canon: Vec<u32> = (0..samples.len() as u32)
        .map(|i| *ids.entry(key(i)).or_insert(i))
        .collect();
    // Per edge (by its canonical ends): each triangle using it, with the
    // edge's ends as that triangle has them.
    type Uses = Vec<(u32, [u32; 2])>;
    let mut by_edge: BTreeMap<(u32, u32), Uses> = BTreeMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            let (ca, cb) = (canon[a as usize], canon[b as usize]);
            if ca != cb {
                by_edge
                    .entry((ca.min(cb), ca.max(cb)))
                    .or_default()
                    .push((t as u32, [a, b]));
            }
        }
    }
    by_edge
        .into_values()
        .filter(|v| v.len() == 2)
        .map(|v| (v[0].1, [v[0].0, v[1].0]))
        .collect()
}

/// The Greville abscissa of control point `i` of the clamped uniform cubic
/// basis with `n` functions.
fn greville(n: usize, i: usize) -> f64 {
    let knots = crate::nurbs::clamped_uniform_knots(n, 3);
    (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0
}

/// Runs a held smoother or sharpener along `path` (model space) on patch
/// `k` of `net`, stopping before a crease tighter than `wall` (the
/// document's print wall); returns the frames applied and why it stopped
/// early, if it did. The patch's displacement is left as after the last
/// frame taken.
pub fn hold_equilibrium(
    net: &mut CurveNetwork,
    k: usize,
    weights: &SurfaceWeights,
    hold: &EquilibriumHold,
    path: &[DVec3],
    wall: f64,
) -> Result<(usize, Option<SurfaceStop>), StylingError> {
    let mut sys = net.surface_system(k, weights)?;
    let n = net.surface_n as usize;
    let (samples, triangles) = net.patch_samples(k);
    let free: Vec<usize> = (0..n * n).filter(|&l| !sys.fixed[l]).collect();
    Budget::default().check_tool_work("path", path.len(), n * n + samples.len() + free.len())?;
    let d0 = net.patches[k].disp.clone();
    let dmin = sys.minimal(&d0)?;
    let mesh = PatchSampler::new(net, k, &samples);
    let sites_at: Vec<MeshSample> = free
        .iter()
        .map(|&l| MeshSample::At(DVec2::new(greville(n, l / n), greville(n, l % n))))
        .collect();
    let sites = PatchSampler::new(net, k, &sites_at);
    let guard = SurfaceGuard::new(&mesh.eval(&d0), triangles, &samples, wall);
    let e: Vec<DVec3> = free
        .iter()
        .map(|&l| DVec3::from_array(d0[l]) - DVec3::from_array(dmin[l]))
        .collect();
    let mut wq: Vec<f64> = vec![1.0; free.len()];
    let mut next = wq.clone();
    let mut d = d0.clone();
    let mut cand = d0.clone();
    for (frame, p) in path.iter().enumerate() {
        let at = hold.radius.map(|_| sites.eval(&d));
        let mut step = 0.0f64;
        for (i, w) in wq.iter().enumerate() {
            let gamma = match (hold.radius, &at) {
                (Some(r), Some(at)) => (-(at[i].distance_squared(*p)) / (r * r)).fexp(),
                _ => 1.0,
            };
            next[i] = (w * (1.0 + gamma * (hold.f - 1.0))).clamp(0.0, hold.wq_max);
            step = step.max((next[i] - w).abs() * e[i].length());
        }
        if let Some(max) = hold.max_step {
            if step > max {
                let s = max / step;
                for (nx, w) in next.iter_mut().zip(&wq) {
                    *nx = w + (*nx - w) * s;
                }
            }
        }
        // The frame, or (when it would overhang or crease) the largest of
        // its half, quarter, ... eighth that does not: the tool then stops
        // there, for the reason the last, smallest part tried was refused.
        let mut part = 1.0;
        let mut why = None;
        let taken = loop {
            for (i, &l) in free.iter().enumerate() {
                let w = wq[i] + (next[i] - wq[i]) * part;
                cand[l] = (DVec3::from_array(dmin[l]) + e[i] * w).to_array();
            }
            match guard.check(&mesh.eval(&cand)) {
                None => break Some(part),
                Some(stop) => why = Some(stop),
            }
            part *= 0.5;
            if part < 0.1 {
                break None;
            }
        };
        if let Some(part) = taken {
            for (w, nx) in wq.iter_mut().zip(&next) {
                *w += (nx - *w) * part;
            }
            d.copy_from_slice(&cand);
        }
        if taken != Some(1.0) {
            net.patches[k].disp = d;
            return Ok((frame + usize::from(taken.is_some()), why));
        }
    }
    if d.iter().flatten().any(|v| !v.is_finite()) {
        return Err(StylingError::NonFinite("surface tool result"));
    }
    net.patches[k].disp = d;
    Ok((path.len(), None))
}

/// Runs the held puller on patch `k` of `net`: the patch point at
/// `(u0, v0)` attracted to each target of `path` in turn (weight `wpp`),
/// stopping before a frame that would make the patch overhang its
/// boundary or crease it tighter than `wall`. Returns the frames applied
/// and the stop, as [`hold_equilibrium`].
pub fn hold_pull(
    net: &mut CurveNetwork,
    k: usize,
    weights: &SurfaceWeights,
    (u0, v0): (f64, f64),
    wpp: f64,
    path: &[DVec3],
    wall: f64,
) -> Result<(usize, Option<SurfaceStop>), StylingError> {
    let mut sys = net.surface_system(k, weights)?;
    let base0 = net.patch_base_point(k, u0, v0)?;
    let (samples, triangles) = net.patch_samples(k);
    Budget::default().check_tool_work("path", path.len(), samples.len())?;
    let mesh = PatchSampler::new(net, k, &samples);
    let d0 = net.patches[k].disp.clone();
    let guard = SurfaceGuard::new(&mesh.eval(&d0), triangles, &samples, wall);
    let mut why = None;
    let mut accept = |d: &[[f64; 3]]| match guard.check(&mesh.eval(d)) {
        None => true,
        Some(stop) => {
            why = Some(stop);
            false
        }
    };
    let (d, frames) = sys.pull_guarded(&d0, u0, v0, base0, wpp, path, &mut accept)?;
    net.patches[k].disp = d;
    Ok((
        frames,
        (frames < path.len()).then(|| why.unwrap_or(SurfaceStop::Overhang)),
    ))
}

#[cfg(test)]
impl PatchSampler {
    /// The largest distance between the sampler's points and `points`
    /// (the patch's own evaluation) with displacement `disp` (tests).
    pub(crate) fn max_gap_to(&self, points: &[DVec3], disp: &[[f64; 3]]) -> f64 {
        self.eval(disp)
            .iter()
            .zip(points)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max)
    }
}
