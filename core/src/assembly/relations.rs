//! Automatic detection of the relations of §3.3 between an assembly's
//! parts: connectivity, coplanarity, concentricity and symmetry.

use glam::DVec3;

use super::structure::{end_radius, mirrored_siblings};
use super::{mirror_gc, project_to_surface};
use crate::gc::{Gc, GcAssembly, Profile};
use crate::nurbs::euclidean;

/// Relations found between parts, each pair `(i, j)` with `i < j` except
/// `connected`, which lists `(child, parent)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Relations {
    /// A part's spine starts (or ends) on another part's side surface,
    /// within the start (end) section's radius.
    pub connected: Vec<(usize, usize)>,
    /// The spine planes coincide.
    pub coplanar: Vec<(usize, usize)>,
    /// Both spines are straight and lie on one line (a shared axis).
    pub concentric: Vec<(usize, usize)>,
    /// Same parent, and one is the mirror image of the other about the
    /// parent's spine plane.
    pub symmetric: Vec<(usize, usize)>,
}

/// The parts whose parent is `part`, in index order.
pub fn children_of(asm: &GcAssembly, part: usize) -> Vec<usize> {
    (0..asm.parts.len())
        .filter(|&c| asm.parts[c].parent == Some(part))
        .collect()
}

/// The spine's control points (Euclidean, model space).
pub fn spine_controls(gc: &Gc) -> Vec<DVec3> {
    gc.spine
        .curve
        .control
        .iter()
        .map(|h| euclidean(*h))
        .collect()
}

/// The diagonal of the spine's control polygon's bounding box (at least
/// 1e-9): the scale relation tolerances are relative to.
pub fn spine_size(gc: &Gc) -> f64 {
    let c = spine_controls(gc);
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in &c {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (hi - lo).length().max(1e-9)
}

fn profile_close(a: &Profile, b: &Profile, tol: f64) -> bool {
    match (a.curve(), b.curve()) {
        (Ok(ca), Ok(cb)) => {
            ca.degree == cb.degree
                && ca.knots.len() == cb.knots.len()
                && ca.control.len() == cb.control.len()
                && ca
                    .knots
                    .iter()
                    .zip(&cb.knots)
                    .all(|(x, y)| (x - y).abs() <= 1e-9)
                && ca
                    .control
                    .iter()
                    .zip(&cb.control)
                    .all(|(x, y)| (*x - *y).abs().max_element() <= tol)
        }
        _ => false,
    }
}

/// True when `b` is `a` mirrored about the plane `(origin, n)`, to a
/// relative tolerance `rel`.
pub(super) fn is_mirror(a: &Gc, b: &Gc, origin: DVec3, n: DVec3, rel: f64) -> bool {
    let tol = rel * spine_size(a);
    let m = mirror_gc(a, origin, n);
    let (cm, cb) = (spine_controls(&m), spine_controls(b));
    m.spine.curve.degree == b.spine.curve.degree
        && m.spine.curve.knots == b.spine.curve.knots
        && cm.len() == cb.len()
        && cm.iter().zip(&cb).all(|(x, y)| x.distance(*y) <= tol)
        && m.spine.plane_normal.dot(b.spine.plane_normal).abs() >= 1.0 - rel
        && m.sections.len() == b.sections.len()
        && m.sections.iter().zip(&b.sections).all(|(x, y)| {
            (x.v - y.v).abs() <= rel
                && (x.scale - y.scale).abs() <= rel * x.scale
                && (x.twist - y.twist).abs() <= rel
                && profile_close(&x.profile, &y.profile, tol)
        })
        && m.shape == b.shape
}

/// The parts mirror-symmetric to `part`: its recorded twins, or, for an
/// assembly without recorded relations (saved before they were
/// recorded), the siblings mirrored about the parent's spine plane
/// (relative tolerance `1e-9` of the part's size) that do not coincide
/// with it.
pub fn symmetry_twins(asm: &GcAssembly, part: usize) -> Vec<usize> {
    if part >= asm.parts.len() {
        return Vec::new();
    }
    if let Some(rec) = &asm.relations {
        return rec.twins_of(part);
    }
    (0..asm.parts.len())
        .filter(|&j| mirrored_siblings(asm, part, j, 1e-9))
        .collect()
}

/// True when `b`'s spine coincides with `a`'s (the same control points to
/// `rel` of the size): one part lying on the other.
pub(super) fn coincident(a: &Gc, b: &Gc, rel: f64) -> bool {
    let tol = rel * spine_size(a);
    let (ca, cb) = (spine_controls(a), spine_controls(b));
    ca.len() == cb.len() && ca.iter().zip(&cb).all(|(x, y)| x.distance(*y) <= tol)
}

/// True when the spines of `a` and `b` lie in one plane (to `rel` of the
/// larger size).
pub(super) fn same_plane(a: &Gc, b: &Gc, rel: f64) -> bool {
    let tol = rel * spine_size(a).max(spine_size(b));
    let (na, nb) = (
        a.spine.plane_normal.normalize(),
        b.spine.plane_normal.normalize(),
    );
    let oa = spine_controls(a)[0];
    na.dot(nb).abs() >= 1.0 - rel
        && spine_controls(b)
            .iter()
            .all(|p| (*p - oa).dot(na).abs() <= tol)
}

/// True when both spines are straight and on one line (to `rel` of the
/// larger size).
pub(super) fn on_one_line(a: &Gc, b: &Gc, rel: f64) -> bool {
    let tol = rel * spine_size(a).max(spine_size(b));
    match (straight_line(a, rel), straight_line(b, rel)) {
        (Some((pa, da)), Some((pb, db))) => {
            let on_line = |p: DVec3| (p - pa).reject_from_normalized(da).length() <= tol;
            da.dot(db).abs() >= 1.0 - rel && on_line(pb) && on_line(pb + db)
        }
        _ => false,
    }
}

fn straight_line(gc: &Gc, rel: f64) -> Option<(DVec3, DVec3)> {
    let c = spine_controls(gc);
    let (a, b) = (*c.first()?, *c.last()?);
    let d = (b - a).try_normalize()?;
    let tol = rel * spine_size(gc);
    c.iter()
        .all(|p| (*p - a).reject_from_normalized(d).length() <= tol)
        .then_some((a, d))
}

/// Detects every relation between the parts of `asm` from their geometry
/// (connectivity is tested for every ordered pair, not read from the
/// parent links). Parts whose surface cannot be built are skipped.
pub fn detect_relations(asm: &GcAssembly) -> Relations {
    let mut rel = Relations::default();
    let n = asm.parts.len();
    let surfaces: Vec<_> = asm.parts.iter().map(|p| p.gc.surface().ok()).collect();
    for i in 0..n {
        let gi = &asm.parts[i].gc;
        let (a, b) = gi.spine.curve.domain();
        let ends = [
            (gi.spine.curve.point(a), end_radius(gi, true)),
            (gi.spine.curve.point(b), end_radius(gi, false)),
        ];
        for (j, surf) in surfaces.iter().enumerate() {
            let Some(surf) = surf else { continue };
            if i == j {
                continue;
            }
            if ends
                .iter()
                .any(|(p, r)| project_to_surface(surf, *p).distance <= r.max(1e-9))
            {
                rel.connected.push((i, j));
            }
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            let (gi, gj) = (&asm.parts[i].gc, &asm.parts[j].gc);
            if same_plane(gi, gj, 1e-9) {
                rel.coplanar.push((i, j));
            }
            if on_one_line(gi, gj, 1e-9) {
                rel.concentric.push((i, j));
            }
            if mirrored_siblings(asm, i, j, 1e-9) {
                rel.symmetric.push((i, j));
            }
        }
    }
    rel
}
