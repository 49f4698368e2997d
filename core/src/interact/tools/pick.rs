//! Ray selection of document objects: a ray against every object's
//! triangle mesh (Möller–Trumbore, after a bounding-box slab test), nearest
//! hit wins. Objects are few and meshes small at VR frame rates, so a
//! per-object box test is enough; a BVH can replace the inner loop when
//! sculpted meshes get large.

use crate::doc::{Document, ObjectId};
use crate::math::DVec3;
use crate::mesh::TriMesh;

/// A ray: origin and unit direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
}

/// The nearest object a ray hits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The object.
    pub id: ObjectId,
    /// Distance along the ray (in the ray's units).
    pub t: f64,
    /// The hit point.
    pub point: DVec3,
    /// The triangle hit.
    pub triangle: usize,
}

/// The nearest hit of `ray` (in model space) with the objects of `doc`
/// within `max_t`. Ties go to the newer object (drawn last, on top).
pub fn pick(doc: &Document, ray: &Ray, max_t: f64) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (id, obj) in doc.objects() {
        let limit = best.map_or(max_t, |b| b.t);
        if let Some((t, tri)) = ray_mesh(ray, &obj.mesh, limit) {
            if best.is_none_or(|b| t <= b.t) {
                best = Some(Hit {
                    id,
                    t,
                    point: ray.origin + ray.dir * t,
                    triangle: tri,
                });
            }
        }
    }
    best
}

/// The nearest hit of `ray` with `mesh` closer than `max_t`: `(t, triangle)`.
pub fn ray_mesh(ray: &Ray, mesh: &TriMesh, max_t: f64) -> Option<(f64, usize)> {
    let (lo, hi) = mesh.bbox()?;
    if !ray_box(ray, lo, hi, max_t) {
        return None;
    }
    let mut best: Option<(f64, usize)> = None;
    for i in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(i);
        if let Some(t) = ray_triangle(ray, a, b, c) {
            if t <= best.map_or(max_t, |b| b.0) {
                best = Some((t, i));
            }
        }
    }
    best
}

fn ray_box(ray: &Ray, lo: DVec3, hi: DVec3, max_t: f64) -> bool {
    let mut t0: f64 = 0.0;
    let mut t1 = max_t;
    for k in 0..3 {
        let (o, d) = (ray.origin[k], ray.dir[k]);
        if d.abs() < 1e-300 {
            if o < lo[k] || o > hi[k] {
                return false;
            }
            continue;
        }
        let (mut a, mut b) = ((lo[k] - o) / d, (hi[k] - o) / d);
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        t0 = t0.max(a);
        t1 = t1.min(b);
        if t0 > t1 {
            return false;
        }
    }
    true
}

/// Möller–Trumbore; both faces hit; `None` for parallel rays and hits
/// behind the origin.
pub fn ray_triangle(ray: &Ray, a: DVec3, b: DVec3, c: DVec3) -> Option<f64> {
    let e1 = b - a;
    let e2 = c - a;
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-18 {
        return None;
    }
    let inv = 1.0 / det;
    let s = ray.origin - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t >= 0.0).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::doc::{AddSolid, Op, OpLog};
    use crate::math::Transform;
    use crate::solid::SolidShape;

    #[test]
    fn picks_the_nearest_sphere_at_its_surface() {
        let mut log = OpLog::new();
        for x in [0.0, 1.0] {
            log.apply(Op::AddSolid(AddSolid {
                shape: SolidShape::Sphere { radius: 0.25 },
                segments: 32,
                transform: Transform::translation([x, 0.0, 0.0]),
            }))
            .unwrap();
        }
        let ray = Ray {
            origin: DVec3::new(-2.0, 0.0, 0.0),
            dir: DVec3::X,
        };
        let hit = pick(log.document(), &ray, 10.0).unwrap();
        assert_eq!(hit.id, ObjectId(1));
        // The tessellated sphere lies within the true one.
        assert!(hit.t > 1.75 - 1e-9 && hit.t < 1.76, "{}", hit.t);
        let miss = Ray {
            origin: DVec3::new(-2.0, 0.5, 0.0),
            dir: DVec3::X,
        };
        assert!(pick(log.document(), &miss, 10.0).is_none());
        // Too short a ray.
        assert!(pick(log.document(), &ray, 1.0).is_none());
        let back = Ray {
            origin: DVec3::new(3.0, 0.0, 0.0),
            dir: DVec3::NEG_X,
        };
        assert_eq!(pick(log.document(), &back, 10.0).unwrap().id, ObjectId(2));
    }
}
