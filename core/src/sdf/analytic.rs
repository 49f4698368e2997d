//! Analytic signed distances of the [`SolidShape`]s, in the shape's own
//! (local) units.
//!
//! Box, sphere, cylinder, cone, torus and capsule are exact distances: the
//! round shapes are solids of revolution around +Z, so their distance is
//! the 2D distance, in the meridian plane `(|p.xy|, z)`, to their profile
//! mirrored about the axis (a convex polygon or a disk). The ellipsoid has
//! no closed form; it uses `(|p / r| - 1) * min(r)`, which has the exact
//! zero set and gradient norm at most 1, so it never overestimates the true
//! distance (the fusion's far-brick test relies on that).

use crate::math::fm::DetMath as _;
use crate::math::DVec3;
use crate::solid::SolidShape;

/// Signed distance from `p` to a convex polygon `poly` (counter-clockwise)
/// in 2D: negative inside.
fn convex_polygon_2d(p: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    let mut dmin = f64::INFINITY;
    let mut inside = true;
    for i in 0..poly.len() {
        let a = poly[i];
        let b = poly[(i + 1) % poly.len()];
        let e = [b[0] - a[0], b[1] - a[1]];
        let w = [p[0] - a[0], p[1] - a[1]];
        let len2 = e[0] * e[0] + e[1] * e[1];
        let t = ((w[0] * e[0] + w[1] * e[1]) / len2).clamp(0.0, 1.0);
        let d = [w[0] - e[0] * t, w[1] - e[1] * t];
        dmin = dmin.min((d[0] * d[0] + d[1] * d[1]).sqrt());
        // Right of a counter-clockwise edge means outside.
        if e[0] * w[1] - e[1] * w[0] < 0.0 {
            inside = false;
        }
    }
    if inside {
        -dmin
    } else {
        dmin
    }
}

/// The signed distance of `shape` (validated) at local point `p`.
pub fn solid_distance(shape: &SolidShape, p: DVec3) -> f64 {
    match *shape {
        SolidShape::Box { size } => {
            let h = DVec3::from_array(size) * 0.5;
            let q = p.abs() - h;
            q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
        }
        SolidShape::Sphere { radius } => p.length() - radius,
        SolidShape::Ellipsoid { radii } => {
            let r = DVec3::from_array(radii);
            ((p / r).length() - 1.0) * r.min_element()
        }
        SolidShape::Cylinder { radius, height } => {
            let h = height / 2.0;
            let q = [p.truncate().length(), p.z];
            convex_polygon_2d(q, &[[-radius, -h], [radius, -h], [radius, h], [-radius, h]])
        }
        SolidShape::Cone { radius, height } => {
            let h = height / 2.0;
            let q = [p.truncate().length(), p.z];
            convex_polygon_2d(q, &[[-radius, -h], [radius, -h], [0.0, h]])
        }
        SolidShape::Torus {
            major_radius,
            minor_radius,
        } => (p.truncate().length() - major_radius).fhypot(p.z) - minor_radius,
        SolidShape::Capsule { radius, length } => {
            let h = length / 2.0;
            let z = p.z.clamp(-h, h);
            (p - DVec3::new(0.0, 0.0, z)).length() - radius
        }
    }
}
