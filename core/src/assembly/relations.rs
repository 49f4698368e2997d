//! Automatic detection of the relations of §3.3 between an assembly's
//! parts: connectivity, coplanarity, concentricity and symmetry.

use glam::DVec3;

use super::{mirror_gc, mirror_plane, project_to_surface};
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

fn controls(gc: &Gc) -> Vec<DVec3> {
    gc.spine
        .curve
        .control
        .iter()
        .map(|h| euclidean(*h))
        .collect()
}

fn size_of(gc: &Gc) -> f64 {
    let c = controls(gc);
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
fn is_mirror(a: &Gc, b: &Gc, origin: DVec3, n: DVec3, rel: f64) -> bool {
    let tol = rel * size_of(a);
    let m = mirror_gc(a, origin, n);
    let (cm, cb) = (controls(&m), controls(b));
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

/// The parts mirror-symmetric to `part`: same parent, mirrored about the
/// parent's spine plane (relative tolerance `1e-9` of the part's size).
pub fn symmetry_twins(asm: &GcAssembly, part: usize) -> Vec<usize> {
    let Some(Some(parent)) = asm.parts.get(part).map(|p| p.parent) else {
        return Vec::new();
    };
    let (o, n) = mirror_plane(&asm.parts[parent].gc);
    let a = &asm.parts[part].gc;
    (0..asm.parts.len())
        .filter(|&j| j != part && asm.parts[j].parent == Some(parent))
        .filter(|&j| is_mirror(a, &asm.parts[j].gc, o, n, 1e-9))
        .collect()
}

fn end_radius(gc: &Gc, first: bool) -> f64 {
    let s = if first {
        gc.sections.first()
    } else {
        gc.sections.last()
    };
    s.and_then(|s| {
        s.profile.curve().ok().map(|c| {
            c.control
                .iter()
                .map(|h| euclidean(*h).truncate().length())
                .fold(0.0, f64::max)
                * s.scale
        })
    })
    .unwrap_or(0.0)
}

fn straight_line(gc: &Gc) -> Option<(DVec3, DVec3)> {
    let c = controls(gc);
    let (a, b) = (*c.first()?, *c.last()?);
    let d = (b - a).try_normalize()?;
    let tol = 1e-9 * size_of(gc);
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
            let tol = 1e-9 * size_of(gi).max(size_of(gj));
            let (ni, nj) = (gi.spine.plane_normal, gj.spine.plane_normal);
            let oi = controls(gi)[0];
            if ni.dot(nj).abs() >= 1.0 - 1e-9
                && controls(gj).iter().all(|p| (*p - oi).dot(ni).abs() <= tol)
            {
                rel.coplanar.push((i, j));
            }
            if let (Some((pa, da)), Some((pb, db))) = (straight_line(gi), straight_line(gj)) {
                let on_line = |p: DVec3| (p - pa).reject_from_normalized(da).length() <= tol;
                if da.dot(db).abs() >= 1.0 - 1e-9 && on_line(pb) && on_line(pb + db) {
                    rel.concentric.push((i, j));
                }
            }
            if symmetry_twins(asm, i).contains(&j) {
                rel.symmetric.push((i, j));
            }
        }
    }
    rel
}
