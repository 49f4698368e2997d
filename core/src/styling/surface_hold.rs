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
//!   boundary is taken only as far as it does not (the largest of its
//!   half, quarter and eighth) and the tool stops there (like the curve
//!   sharpener's limits, not an error: the frames before are kept). The
//!   patch's mesh (what prints) overhangs when a triangle that faced along
//!   the loop's normal at activation (the vector area of the boundary,
//!   which no tool changes) turns to face against it or collapses: the
//!   surface then folds back over its boundary, which is what made the
//!   print refuse to thicken sharpened 7-, 12- and 16-gons. The puller
//!   stops the same way.
//!
//! The patch's mesh is evaluated once at activation as base points plus
//! displacement coefficients (`PatchSampler`), so a frame costs a sparse
//! product, not a re-evaluation of the (transfinite) base surface.

use crate::math::fm::DetMath as _;
use serde::{Deserialize, Serialize};

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

/// Watches a patch's mesh for an overhang over its boundary (see the
/// module doc).
pub(crate) struct OverhangGuard {
    triangles: Vec<[u32; 3]>,
    /// Per triangle, the direction it must keep facing along (`None`: not
    /// watched, it did not face along the loop's normal at activation).
    facing: Vec<Option<DVec3>>,
}

/// A triangle faces along `dir` when its normal's component along `dir`
/// is above this fraction of its length (a margin for rounding: the
/// sampler's sums differ from the mesh's in the last bits).
const FACING_MARGIN: f64 = 1e-6;

fn normal_of(p: &[DVec3], t: &[u32; 3]) -> DVec3 {
    let [a, b, c] = t.map(|i| p[i as usize]);
    (b - a).cross(c - a)
}

impl OverhangGuard {
    /// Watches the mesh `points`/`triangles` as it is at activation.
    pub(crate) fn new(points: &[DVec3], triangles: Vec<[u32; 3]>) -> Self {
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
        Self { triangles, facing }
    }

    /// Whether the mesh `points` keeps every watched triangle facing its
    /// way, without collapsing.
    pub(crate) fn accepts(&self, points: &[DVec3]) -> bool {
        self.triangles.iter().zip(&self.facing).all(|(t, dir)| {
            let Some(dir) = dir else { return true };
            let n = normal_of(points, t);
            let l = n.length();
            l.is_finite() && l > 0.0 && n.dot(*dir) > FACING_MARGIN * l
        })
    }
}

/// The Greville abscissa of control point `i` of the clamped uniform cubic
/// basis with `n` functions.
fn greville(n: usize, i: usize) -> f64 {
    let knots = crate::nurbs::clamped_uniform_knots(n, 3);
    (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0
}

/// Runs a held smoother or sharpener along `path` (model space) on patch
/// `k` of `net`; returns the frames applied and why it stopped early, if
/// it did. The patch's displacement is left as after the last frame taken.
pub fn hold_equilibrium(
    net: &mut CurveNetwork,
    k: usize,
    weights: &SurfaceWeights,
    hold: &EquilibriumHold,
    path: &[DVec3],
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
    let guard = OverhangGuard::new(&mesh.eval(&d0), triangles);
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
        // The frame, or (when it would overhang) the largest of its half,
        // quarter, ... eighth that does not: the tool then stops there.
        let mut part = 1.0;
        let taken = loop {
            for (i, &l) in free.iter().enumerate() {
                let w = wq[i] + (next[i] - wq[i]) * part;
                cand[l] = (DVec3::from_array(dmin[l]) + e[i] * w).to_array();
            }
            if guard.accepts(&mesh.eval(&cand)) {
                break Some(part);
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
            return Ok((
                frame + usize::from(taken.is_some()),
                Some(SurfaceStop::Overhang),
            ));
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
/// boundary. Returns the frames applied and the stop, as
/// [`hold_equilibrium`].
pub fn hold_pull(
    net: &mut CurveNetwork,
    k: usize,
    weights: &SurfaceWeights,
    (u0, v0): (f64, f64),
    wpp: f64,
    path: &[DVec3],
) -> Result<(usize, Option<SurfaceStop>), StylingError> {
    let mut sys = net.surface_system(k, weights)?;
    let base0 = net.patch_base_point(k, u0, v0)?;
    let (samples, triangles) = net.patch_samples(k);
    Budget::default().check_tool_work("path", path.len(), samples.len())?;
    let mesh = PatchSampler::new(net, k, &samples);
    let d0 = net.patches[k].disp.clone();
    let guard = OverhangGuard::new(&mesh.eval(&d0), triangles);
    let mut accept = |d: &[[f64; 3]]| guard.accepts(&mesh.eval(d));
    let (d, frames) = sys.pull_guarded(&d0, u0, v0, base0, wpp, path, &mut accept)?;
    net.patches[k].disp = d;
    Ok((
        frames,
        (frames < path.len()).then_some(SurfaceStop::Overhang),
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
