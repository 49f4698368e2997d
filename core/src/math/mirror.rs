//! A mirror plane placed by the user (issue 19's mirror symmetry): where a
//! point, a brush pose or a curve goes in the mirror image.
//!
//! A reflection `M = I − 2nnᵀ` is not a rotation (det −1), so an oriented
//! frame `O` cannot simply be reflected: its mirror image is `M·O·P`, with
//! `P` the reflection across the frame's own x = 0 plane. That is a proper
//! rotation again, and it covers the same region as `M·O` for any shape
//! symmetric across its local x = 0 plane (the brush presets: sphere,
//! ellipsoid, box, capsule). Between two frames its increment is
//! `M·(O₂O₁⁻¹)·M`, the mirror image of the motion, so a twist mirrors to
//! the opposite twist. On quaternions: `M·R·M` of `(v, w)` is
//! `(−v + 2(v·n)n, w)`.

use glam::{DMat3, DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::LENGTH_EPS;

/// `p` reflected about the plane through `origin` with unit normal `n`.
pub fn reflect(p: DVec3, origin: DVec3, n: DVec3) -> DVec3 {
    p - n * (2.0 * (p - origin).dot(n))
}

/// A plane in document space: strokes made with it set are mirrored
/// across it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MirrorPlane {
    /// A point on the plane (metres, document space).
    pub point: [f64; 3],
    /// The plane's normal (any length but zero).
    pub normal: [f64; 3],
}

/// What was wrong with a mirror plane.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MirrorError {
    /// A component is NaN or infinite.
    #[error("mirror plane {field} has a non-finite component: {value:?}")]
    NonFinite {
        /// `point` or `normal`.
        field: &'static str,
        /// The offending values.
        value: [f64; 3],
    },
    /// The normal has (near) zero length and names no plane.
    #[error("mirror plane normal {0:?} has zero length; give the direction across the plane")]
    ZeroNormal([f64; 3]),
}

impl MirrorPlane {
    /// The plane through `point` across unit direction `normal`
    /// (normalized here).
    pub fn new(point: DVec3, normal: DVec3) -> Result<Self, MirrorError> {
        let p = Self {
            point: point.to_array(),
            normal: normal.to_array(),
        };
        p.validate()?;
        Ok(Self {
            normal: normal.normalize().to_array(),
            ..p
        })
    }

    /// Checks the plane is finite with a non-zero normal.
    pub fn validate(&self) -> Result<(), MirrorError> {
        for (field, value) in [("point", self.point), ("normal", self.normal)] {
            if !super::all_finite(&value) {
                return Err(MirrorError::NonFinite { field, value });
            }
        }
        if DVec3::from_array(self.normal).length() < LENGTH_EPS {
            return Err(MirrorError::ZeroNormal(self.normal));
        }
        Ok(())
    }

    fn unit_normal(&self) -> DVec3 {
        DVec3::from_array(self.normal).normalize_or_zero()
    }

    /// `p` reflected across the plane.
    pub fn point(&self, p: DVec3) -> DVec3 {
        reflect(p, DVec3::from_array(self.point), self.unit_normal())
    }

    /// A direction reflected across the plane.
    pub fn vector(&self, v: DVec3) -> DVec3 {
        let n = self.unit_normal();
        v - n * (2.0 * v.dot(n))
    }

    /// The mirror image of frame `o`: `M·o·P` (see the module doc).
    pub fn frame(&self, o: DQuat) -> DQuat {
        let n = self.unit_normal();
        let m = DMat3::IDENTITY - 2.0 * DMat3::from_cols(n * n.x, n * n.y, n * n.z);
        let p = DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0));
        DQuat::from_mat3(&(m * DMat3::from_quat(o.normalize()) * p)).normalize()
    }

    /// The mirror image of rotation `r` (as a motion): `M·r·M`.
    pub fn rotation(&self, r: DQuat) -> DQuat {
        let n = self.unit_normal();
        let v = DVec3::new(r.x, r.y, r.z);
        let v = -v + n * (2.0 * v.dot(n));
        DQuat::from_xyzw(v.x, v.y, v.z, r.w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane() -> MirrorPlane {
        MirrorPlane::new(DVec3::new(0.1, -0.2, 0.3), DVec3::new(1.0, 2.0, -0.5)).unwrap()
    }

    #[test]
    fn reflecting_twice_is_the_identity_and_points_on_the_plane_stay() {
        let m = plane();
        let p = DVec3::new(0.7, 0.4, -1.1);
        assert!(m.point(m.point(p)).distance(p) < 1e-12);
        let on = DVec3::from_array(m.point);
        assert!(m.point(on).distance(on) < 1e-15);
        // The midpoint of p and its image lies on the plane, the segment
        // across it.
        let q = m.point(p);
        let n = DVec3::from_array(m.normal);
        assert!(((p + q) * 0.5 - on).dot(n).abs() < 1e-12);
        assert!((q - p).cross(n).length() < 1e-12);
    }

    #[test]
    fn a_mirrored_frame_is_a_rotation_covering_the_mirrored_region() {
        let m = plane();
        let o = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7);
        let f = m.frame(o);
        assert!((f.length() - 1.0).abs() < 1e-12);
        // Its y and z axes are the mirrored ones; x flips (the brush shape
        // is symmetric across its x = 0 plane).
        for (axis, sign) in [(DVec3::X, -1.0), (DVec3::Y, 1.0), (DVec3::Z, 1.0)] {
            let want = m.vector(o * axis) * sign;
            assert!((f * axis).distance(want) < 1e-12, "{axis}");
        }
    }

    #[test]
    fn the_increment_between_mirrored_frames_is_the_mirrored_motion() {
        let m = plane();
        let a = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7);
        let b = DQuat::from_euler(glam::EulerRot::XYZ, 0.5, -0.9, 1.2);
        let inc = (m.frame(b) * m.frame(a).inverse()).normalize();
        let want = m.rotation(b * a.inverse());
        // Same rotation (q and -q are the same).
        assert!(inc.dot(want).abs() > 1.0 - 1e-12);
        // A motion and its mirror turn the same angle.
        let (_, t1) = (b * a.inverse()).to_axis_angle();
        let (_, t2) = want.to_axis_angle();
        assert!((t1 - t2).abs() < 1e-9);
        // Turning about a point of the plane: the mirrored motion moves a
        // point where the motion moves its image, mirrored back.
        let x = DVec3::new(0.2, 0.9, -0.4);
        let about_plane = |r: DQuat, p: DVec3| {
            let o = DVec3::from_array(m.point);
            r * (p - o) + o
        };
        let lhs = m.point(about_plane(b * a.inverse(), m.point(x)));
        let rhs = about_plane(want, x);
        assert!(lhs.distance(rhs) < 1e-12);
    }

    #[test]
    fn bad_planes_are_typed_errors() {
        assert!(matches!(
            MirrorPlane::new(DVec3::ZERO, DVec3::ZERO),
            Err(MirrorError::ZeroNormal(_))
        ));
        assert!(matches!(
            MirrorPlane::new(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::X),
            Err(MirrorError::NonFinite { field: "point", .. })
        ));
    }
}
