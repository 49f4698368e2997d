//! An object's *origin*: the frame a host shows as the object's own (the
//! point Blender's R and S pivot about, the axes its N panel shows), and
//! the object's mesh in that frame. One rule for every host, so Blender,
//! its USD export and the headset agree on where an object is:
//!
//! - **Solids and sculpts** carry their own transform (their ops place
//!   them); the origin is that transform: a solid's centre with its
//!   rotation and scale, a sculpt's base centre.
//! - **GC assemblies, SDF volumes and curve networks** keep their
//!   geometry in their own frame under an object-level placement; the
//!   origin is the placement moved to the centre of the bounding box of
//!   that geometry (in its own frame, so moving, turning or scaling the
//!   object never moves the origin within it; an edit that changes the
//!   geometry's extent does). An object with no triangles yet (a curve
//!   network before its first patch) has its origin at its placement.
//!
//! A host that lets a person move the origin's frame (Blender's G, R, S)
//! records [`Object::placement_for_origin`] as a `set_transform` op: the
//! placement that puts the origin where the person put it.

use crate::math::{DVec3, Transform};
use crate::mesh::TriMesh;

use super::{Object, OpError};

impl Object {
    /// The centre of the own-frame geometry's bounding box that the origin
    /// sits on, for kinds placed by the object (zero for the others and for
    /// empty meshes).
    fn origin_offset(&self) -> DVec3 {
        if self.kind.own_transform().is_some() {
            return DVec3::ZERO;
        }
        self.local_mesh
            .bbox()
            .map_or(DVec3::ZERO, |(lo, hi)| (lo + hi) / 2.0)
    }

    /// The object's origin (see the module doc).
    pub fn origin(&self) -> Transform {
        if let Some(t) = self.kind.own_transform() {
            return t;
        }
        let p = self.placement;
        let c = self.origin_offset();
        // p ∘ translate(c): x -> t + R S (x + c).
        let rs =
            crate::math::DQuat::from_array(p.rotate).normalize() * (DVec3::from_array(p.scale) * c);
        Transform {
            translate: (DVec3::from_array(p.translate) + rs).to_array(),
            ..p
        }
    }

    /// The transform a `set_transform` op sets so that the object's origin
    /// becomes `origin` (the object moved rigidly with it).
    pub fn placement_for_origin(&self, origin: &Transform) -> Result<Transform, OpError> {
        origin.validate()?;
        if self.kind.own_transform().is_some() {
            return Ok(*origin);
        }
        let c = self.origin_offset();
        // origin ∘ translate(-c).
        let rs = crate::math::DQuat::from_array(origin.rotate).normalize()
            * (DVec3::from_array(origin.scale) * c);
        Ok(Transform {
            translate: (DVec3::from_array(origin.translate) - rs).to_array(),
            ..*origin
        })
    }

    /// The object's mesh in its origin's frame: [`Self::origin`] applied
    /// to it gives [`Object::mesh`] (up to rounding). It depends on the
    /// shape only, never on where the object is: a solid's tessellation
    /// and a sculpt's surface before their transform, the own-frame
    /// geometry of the other kinds moved by the offset. Its triangles face
    /// outward in the origin's frame; under a mirroring origin (a negative
    /// scale) the placed mesh has them in the other order, as every host
    /// that draws a mirrored object expects.
    pub fn origin_mesh(&self) -> Result<TriMesh, OpError> {
        let mut out = match &self.kind {
            super::ObjectKind::Solid(s) => crate::solid::tessellate(&s.shape, s.segments)?,
            super::ObjectKind::SculptMesh(s) => s.surface.to_trimesh(),
            _ => {
                let mut m = (*self.local_mesh).clone();
                let c = self.origin_offset();
                for p in &mut m.positions {
                    *p = (DVec3::from_array(*p) - c).to_array();
                }
                m
            }
        };
        out.set_source(self.mesh.tri_source.first().copied().unwrap_or(0));
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use crate::doc::{Op, OpLog};
    use crate::math::fm::DetMath as _;
    use crate::math::Transform;

    fn apply(log: &mut OpLog, json: &str) -> crate::doc::ObjectId {
        let op: Op = serde_json::from_str(json).unwrap();
        let out = log.apply(op).unwrap();
        out.created.unwrap_or(crate::doc::ObjectId(1))
    }

    /// A straight generalized cylinder at x = 0.5 (its centre at z = 0.1).
    const GC: &str = r#"{"op":"gc_create","spine":[[0.5,0,0],[0.5,0,0.2]],"plane_normal":[0,1,0],"sections":[{"profile":{"template":"circle","radius":0.05},"v":0},{"profile":{"template":"circle","radius":0.05},"v":1}],"shape":{"type":"solid"},"resolution":{"u":32,"v":16}}"#;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    #[test]
    fn a_solid_s_origin_is_its_centre_and_a_gc_s_the_centre_of_its_box() {
        let mut log = OpLog::new();
        let s = apply(
            &mut log,
            r#"{"op":"add_solid","shape":{"kind":"sphere","radius":0.1},"transform":{"translate":[0.3,0.2,0.1]}}"#,
        );
        let solid = log.document().get(s).unwrap();
        assert_eq!(solid.origin().translate, [0.3, 0.2, 0.1]);
        let g = apply(&mut log, GC);
        let gc = log.document().get(g).unwrap();
        let (lo, hi) = gc.mesh.bbox().unwrap();
        let centre = ((lo + hi) / 2.0).to_array();
        assert!(close(gc.origin().translate, centre), "{:?}", gc.origin());
    }

    #[test]
    fn the_origin_mesh_placed_by_the_origin_is_the_mesh() {
        let mut log = OpLog::new();
        let g = apply(&mut log, GC);
        apply(
            &mut log,
            r#"{"op":"transform_by","id":1,"transform":{"translate":[0.1,-0.2,0.3],"rotate":[0,0,0.38268343236508984,0.9238795325112867],"scale":[2,2,2]}}"#,
        );
        let s = apply(
            &mut log,
            r#"{"op":"add_solid","shape":{"kind":"box","size":[0.1,0.2,0.3]},"transform":{"translate":[0.3,0.2,0.1],"rotate":[0.2,0.1,0,0.97],"scale":[1,2,3]}}"#,
        );
        for id in [g, s] {
            let obj = log.document().get(id).unwrap();
            let local = obj.origin_mesh().unwrap();
            let a = obj.origin().to_affine().unwrap();
            for (p, q) in local.positions.iter().zip(&obj.mesh.positions) {
                let placed = a.transform_point3(crate::math::DVec3::from_array(*p));
                assert!(
                    (placed - crate::math::DVec3::from_array(*q)).length() < 1e-12,
                    "{id:?}: {placed} vs {q:?}"
                );
            }
            assert_eq!(local.triangles, obj.mesh.triangles);
        }
    }

    #[test]
    fn moving_the_origin_moves_the_object_and_keeps_the_origin_where_put() {
        let mut log = OpLog::new();
        let g = apply(&mut log, GC);
        let before = log.document().get(g).unwrap().origin();
        // Turned 90 degrees about its own centre: the centre stays put.
        let h = std::f64::consts::FRAC_PI_4;
        let turned = Transform {
            rotate: [h.fsin(), 0.0, 0.0, h.fcos()],
            ..before
        };
        let t = log
            .document()
            .get(g)
            .unwrap()
            .placement_for_origin(&turned)
            .unwrap();
        let op = Op::SetTransform(crate::doc::SetTransform {
            id: g,
            transform: t,
        });
        log.apply(op).unwrap();
        let after = log.document().get(g).unwrap().origin();
        assert!(
            close(after.translate, before.translate),
            "{after:?} vs {before:?}"
        );
        let (lo, hi) = log.document().get(g).unwrap().mesh.bbox().unwrap();
        assert!(close(((lo + hi) / 2.0).to_array(), before.translate));
    }
}
