//! Where a child sits on its parent: surface parameters, closest-point
//! projection onto a GC's side surface, and the sketch frame
//! `(n, t, n x t)` at an anchor.

use glam::{DAffine3, DVec3};
use serde::{Deserialize, Serialize};

use super::AssemblyError;
use crate::gc::Gc;
use crate::nurbs::NurbsSurface;

/// A point of a parent's side surface `S(u, v)` (`u` around the sections,
/// `v` the spine parameter).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Anchor {
    /// Parameter around the section.
    pub u: f64,
    /// Spine parameter.
    pub v: f64,
}

/// How a child is attached to its parent: its spine starts at `start`,
/// and a handle's spine also ends at `end` (a spout's end is free).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Attachment {
    /// Anchor of the spine's start (the picked point).
    pub start: Anchor,
    /// Anchor of the spine's end, for a handle.
    pub end: Option<Anchor>,
}

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
    let (mut u, mut v) = (us[best.0 % SEED_U], vs[best.0 / SEED_U]);
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
