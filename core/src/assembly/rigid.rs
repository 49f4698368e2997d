//! Moving GCs: similarity transforms (rotation, translation, uniform
//! scale of the spine) and mirroring about a plane.
//!
//! A GC's sections live in the rotation-minimizing frames of its spine,
//! and double reflection commutes with orthogonal maps, so transforming
//! the spine's control points and plane normal moves the whole surface
//! rigidly. A reflection maps the RMF `(r, s, t)` to `(M r, -M s, M t)`
//! (a cross product flips under a reflection), so the mirrored GC's
//! sections are the originals flipped in local `y`, their twist negated.

use glam::{DAffine3, DMat3, DVec3};

use crate::gc::{Gc, KeySection, Profile};
use crate::nurbs::{euclidean, homogeneous, NurbsCurve};

/// `gc` with its spine mapped by `m`, a rotation plus translation, with
/// an optional uniform scale (the sections keep their size).
pub fn transform_gc(gc: &Gc, m: &DAffine3) -> Gc {
    let mut out = gc.clone();
    out.spine.curve = gc.spine.curve.transformed(m);
    out.spine.plane_normal = (m.matrix3 * gc.spine.plane_normal).normalize();
    out
}

/// The mirror plane of a parent: through its spine's first control point,
/// normal to its spine plane.
pub fn mirror_plane(parent: &Gc) -> (DVec3, DVec3) {
    let o = parent
        .spine
        .curve
        .control
        .first()
        .map(|h| euclidean(*h))
        .unwrap_or(DVec3::ZERO);
    (o, parent.spine.plane_normal.normalize())
}

pub use crate::math::reflect;

fn flip_y_curve(c: &NurbsCurve) -> NurbsCurve {
    let flip = DAffine3::from_mat3(DMat3::from_diagonal(DVec3::new(1.0, -1.0, 1.0)));
    c.transformed(&flip).reversed()
}

/// A profile flipped in local `y` (and kept counter-clockwise). The
/// circle, ellipse and rectangle templates are symmetric in `y`.
pub fn flip_profile(p: &Profile) -> Profile {
    match p {
        Profile::Circle { .. } | Profile::Ellipse { .. } | Profile::Rectangle { .. } => p.clone(),
        // Reversed to stay counter-clockwise, but from the same first
        // point: the loft matches sections by their start points, so a
        // rotated start would twist the surface between key sections.
        Profile::Points { points } => Profile::Points {
            points: points
                .iter()
                .take(1)
                .chain(points.iter().skip(1).rev())
                .map(|q| [q[0], -q[1]])
                .collect(),
        },
        Profile::Polygon { .. } => match p.curve() {
            Ok(c) => Profile::Curve {
                curve: flip_y_curve(&c),
            },
            Err(_) => p.clone(),
        },
        Profile::Curve { curve } => Profile::Curve {
            curve: flip_y_curve(curve),
        },
    }
}

/// `gc` mirrored about the plane through `origin` with unit normal `n`.
pub fn mirror_gc(gc: &Gc, origin: DVec3, n: DVec3) -> Gc {
    let mut out = gc.clone();
    for h in &mut out.spine.curve.control {
        *h = homogeneous(reflect(euclidean(*h), origin, n), h.w);
    }
    let pn = gc.spine.plane_normal;
    out.spine.plane_normal = (pn - n * (2.0 * pn.dot(n))).normalize();
    out.sections = gc
        .sections
        .iter()
        .map(|s| KeySection {
            profile: flip_profile(&s.profile),
            v: s.v,
            scale: s.scale,
            twist: -s.twist,
        })
        .collect();
    out
}
