//! Where a child sits on its parent: surface parameters, closest-point
//! projection onto a GC's side surface, and the sketch frame
//! `(n, t, n x t)` at an anchor.

use glam::{DAffine3, DVec3};

use super::AssemblyError;
use crate::gc::{Anchor, Gc};
use crate::nurbs::NurbsSurface;

/// The closest point of a surface to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Its parameters.
    pub anchor: Anchor,
    /// The surface point.
    pub point: DVec3,
    /// Distance from the query point.
    pub distance: f64,
}

const SEED_U: usize = 64;
const SEED_V: usize = 48;

/// Closest point of `surf` to `p`: the nearest of a `64 x 48` parameter
/// grid, refined by Newton's method on `|S(u, v) - p|^2` (`u` wraps, as
/// the sections are closed; `v` is clamped to the domain).
pub fn project_to_surface(surf: &NurbsSurface, p: DVec3) -> Projection {
    let ((u0, u1), (v0, v1)) = surf.domain();
    let us: Vec<f64> = (0..SEED_U)
        .map(|i| u0 + (u1 - u0) * i as f64 / SEED_U as f64)
        .collect();
    let vs: Vec<f64> = (0..=SEED_V)
        .map(|j| v0 + (v1 - v0) * j as f64 / SEED_V as f64)
        .collect();
    let grid = surf.grid(&us, &vs);
    let mut best = (0usize, f64::INFINITY);
    for (k, q) in grid.iter().enumerate() {
        let d = q.distance_squared(p);
        if d < best.1 {
            best = (k, d);
        }
    }
    project_near(
        surf,
        p,
        Anchor {
            u: us[best.0 % SEED_U],
            v: vs[best.0 / SEED_U],
        },
    )
}

/// The closest point of `surf` to `p` near `seed`: Newton's method on
/// `|S(u, v) - p|^2` from `seed` (`u` wraps, `v` is clamped to the
/// domain). A local minimum: [`project_to_surface`] seeds it from a grid,
/// callers that walk along a curve seed it from the previous point.
pub fn project_near(surf: &NurbsSurface, p: DVec3, seed: Anchor) -> Projection {
    let ((u0, u1), (v0, v1)) = surf.domain();
    let (mut u, mut v) = (seed.u, seed.v);
    let period = u1 - u0;
    for _ in 0..32 {
        let d = surf.derivatives(u, v, 2);
        let r = d[0][0] - p;
        let (su, sv) = (d[1][0], d[0][1]);
        let (suu, suv, svv) = (d[2][0], d[1][1], d[0][2]);
        let g = DVec3::new(su.dot(r), sv.dot(r), 0.0);
        let (a, b, c) = (
            su.dot(su) + suu.dot(r),
            su.dot(sv) + suv.dot(r),
            sv.dot(sv) + svv.dot(r),
        );
        let det = a * c - b * b;
        let (du, dv) = if det > 1e-300 && a > 0.0 {
            ((c * g.x - b * g.y) / det, (a * g.y - b * g.x) / det)
        } else {
            // Gauss-Newton step when the Hessian is not positive definite.
            let (a, c) = (su.dot(su).max(1e-300), sv.dot(sv).max(1e-300));
            (g.x / a, g.y / c)
        };
        if !(du.is_finite() && dv.is_finite()) {
            break;
        }
        let (du, dv) = (
            du.clamp(-0.1 * period, 0.1 * period),
            dv.clamp(-0.1 * (v1 - v0), 0.1 * (v1 - v0)),
        );
        u -= du;
        v = (v - dv).clamp(v0, v1);
        if u < u0 {
            u += period;
        } else if u >= u1 {
            u -= period;
        }
        if du.abs() < 1e-15 * period && dv.abs() < 1e-15 * (v1 - v0) {
            break;
        }
    }
    let point = surf.point(u, v);
    Projection {
        anchor: Anchor { u, v },
        point,
        distance: point.distance(p),
    }
}

/// The sketch frame at `anchor` on `parent` (whose side surface is
/// `surf`): columns `n` (outward surface normal), `t` (the parent's spine
/// tangent made perpendicular to `n`), `n x t` (the normal of a child's
/// spine plane), and the surface point as origin.
pub fn anchor_frame(
    parent: &Gc,
    surf: &NurbsSurface,
    anchor: Anchor,
) -> Result<DAffine3, AssemblyError> {
    let Anchor { u, v } = anchor;
    let bad = AssemblyError::DegenerateAnchor { u, v };
    let d = surf.derivatives(u, v, 1);
    let n = d[1][0].cross(d[0][1]).try_normalize().ok_or(bad.clone())?;
    let t_spine = parent.spine.curve.derivatives(v, 1)[1];
    let t = (t_spine - n * n.dot(t_spine)).try_normalize().ok_or(bad)?;
    Ok(DAffine3::from_cols(n, t, n.cross(t), d[0][0]))
}

/// Samples of an iso-curve searched for where it crosses a plane.
const PLANE_SAMPLES: usize = 256;

/// The anchor frame at spine parameter `anchor.v` of `parent` kept in a
/// plane (a coplanar relation): the point of the iso-curve `S(., v)`
/// nearest to `anchor.u` (around the loop) whose signed distance from the
/// plane through `o` with unit normal `pn` is `offset`, and there the
/// frame `(n', t', ±pn)` with `n'` the surface normal turned into the
/// plane. A child placed by such frames stays in the plane whatever the
/// parent's parameterization does (a section replaced by another profile
/// kind moves the point at a fixed `u`). `None` when the iso-curve does
/// not reach that distance.
pub fn anchor_frame_in_plane(
    parent: &Gc,
    surf: &NurbsSurface,
    anchor: Anchor,
    (o, pn): (DVec3, DVec3),
    offset: f64,
) -> Option<(Anchor, DAffine3)> {
    let ((u0, u1), _) = surf.domain();
    let period = u1 - u0;
    let v = anchor.v;
    let f = |u: f64| (surf.point(u, v) - o).dot(pn) - offset;
    // Already there (to rounding): the anchor stays as it is.
    let p = surf.point(anchor.u, v);
    let scale = (p - o).length().max(p.length()).max(1e-9);
    let found = if f(anchor.u).abs() <= 1e-13 * scale {
        Some(anchor.u)
    } else {
        crossing_nearest(&f, anchor.u, (u0, u1))
    };
    let u = found?;
    let u = if u >= u1 { u - period } else { u };
    let at = Anchor { u, v };
    let f = anchor_frame(parent, surf, at).ok()?;
    let pn = pn.normalize();
    let z = if f.matrix3.z_axis.dot(pn) >= 0.0 {
        pn
    } else {
        -pn
    };
    let n = f.matrix3.x_axis;
    let x = (n - pn * n.dot(pn)).try_normalize()?;
    let y = z.cross(x);
    Some((at, DAffine3::from_cols(x, y, z, f.translation)))
}

/// The zero of `f` (sampled at [`PLANE_SAMPLES`] steps over the periodic
/// domain `(u0, u1)`, refined by bisection) nearest to `near` around the
/// loop.
fn crossing_nearest(f: &dyn Fn(f64) -> f64, near: f64, (u0, u1): (f64, f64)) -> Option<f64> {
    let period = u1 - u0;
    let us: Vec<f64> = (0..=PLANE_SAMPLES)
        .map(|i| u0 + period * i as f64 / PLANE_SAMPLES as f64)
        .collect();
    let fs: Vec<f64> = us.iter().map(|&u| f(u)).collect();
    let cyclic = |u: f64| {
        let d = (u - near).rem_euclid(period);
        d.min(period - d)
    };
    let mut best: Option<(f64, f64)> = None;
    for i in 0..PLANE_SAMPLES {
        let (mut a, mut b, mut fa) = (us[i], us[i + 1], fs[i]);
        if fa == 0.0 {
            b = a;
        } else if fa * fs[i + 1] > 0.0 || fs[i + 1] == 0.0 {
            continue;
        } else {
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if !(m > a && m < b) {
                    break;
                }
                let fm = f(m);
                if fm == 0.0 {
                    (a, b) = (m, m);
                    break;
                }
                if fm * fa < 0.0 {
                    b = m;
                } else {
                    (a, fa) = (m, fm);
                }
            }
        }
        let root = if (f(a)).abs() <= (f(b)).abs() { a } else { b };
        if best.is_none_or(|(_, d)| cyclic(root) < d) {
            best = Some((root, cyclic(root)));
        }
    }
    best.map(|(u, _)| u)
}
