//! Transforms as they appear in ops: translation, rotation and per-axis
//! scale, applied in the order scale, then rotate, then translate.

use glam::{DAffine3, DQuat, DVec3};
use serde::{Deserialize, Serialize};

/// A transform as ops carry it: `p' = translate + rotate * (scale * p)`.
///
/// The rotation is a quaternion `[x, y, z, w]`; it is normalized when the
/// transform is built, and must not be zero. Every field has a default, so
/// scripts may give only what they change.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Transform {
    /// Translation in model units.
    #[schemars(extend("x-unit" = "m"))]
    pub translate: [f64; 3],
    /// Rotation quaternion `[x, y, z, w]`.
    pub rotate: [f64; 4],
    /// Scale per axis; every component must be non-zero.
    pub scale: [f64; 3],
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// What was wrong with a transform.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TransformError {
    /// A component is NaN or infinite; tracking was probably lost.
    #[error("transform {field} has a non-finite component: {value:?}")]
    NonFinite {
        /// Which field (`translate`, `rotate`, `scale`).
        field: &'static str,
        /// The offending values.
        value: Vec<f64>,
    },
    /// The rotation quaternion has (near) zero length and names no rotation.
    #[error("transform rotate is a zero quaternion; give [x, y, z, w] with w = 1 for no rotation")]
    ZeroRotation,
    /// A scale component is zero (or too close to it), which would flatten
    /// the object and make the transform singular.
    #[error("transform scale {0:?} has a zero component; scales must be non-zero")]
    SingularScale([f64; 3]),
}

impl Transform {
    /// No change.
    pub const IDENTITY: Self = Self {
        translate: [0.0; 3],
        rotate: [0.0, 0.0, 0.0, 1.0],
        scale: [1.0; 3],
    };

    /// A pure translation.
    pub fn translation(t: [f64; 3]) -> Self {
        Self {
            translate: t,
            ..Self::IDENTITY
        }
    }

    /// Checks the transform and returns it as an affine matrix.
    pub fn to_affine(&self) -> Result<DAffine3, TransformError> {
        self.validate()?;
        let q = DQuat::from_array(self.rotate).normalize();
        Ok(DAffine3::from_scale_rotation_translation(
            DVec3::from_array(self.scale),
            q,
            DVec3::from_array(self.translate),
        ))
    }

    /// Checks that the transform is finite, its rotation non-zero and its
    /// scale non-singular.
    pub fn validate(&self) -> Result<(), TransformError> {
        check_finite("translate", &self.translate)?;
        check_finite("rotate", &self.rotate)?;
        check_finite("scale", &self.scale)?;
        let qn = self.rotate.iter().map(|x| x * x).sum::<f64>();
        if qn < 1e-24 {
            return Err(TransformError::ZeroRotation);
        }
        if self.scale.iter().any(|s| s.abs() < 1e-12) {
            return Err(TransformError::SingularScale(self.scale));
        }
        Ok(())
    }
}

fn check_finite(field: &'static str, v: &[f64]) -> Result<(), TransformError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(TransformError::NonFinite {
            field,
            value: v.to_vec(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trs_order_is_scale_rotate_translate() {
        let t = Transform {
            translate: [1.0, 0.0, 0.0],
            rotate: DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2).to_array(),
            scale: [2.0, 1.0, 1.0],
        };
        let p = t.to_affine().unwrap().transform_point3(DVec3::X);
        assert!((p - DVec3::new(1.0, 2.0, 0.0)).length() < 1e-12, "{p}");
    }

    #[test]
    fn rejects_bad_transforms() {
        let mut t = Transform::IDENTITY;
        t.translate[1] = f64::NAN;
        assert!(matches!(
            t.validate(),
            Err(TransformError::NonFinite {
                field: "translate",
                ..
            })
        ));
        let mut t = Transform::IDENTITY;
        t.rotate = [0.0; 4];
        assert_eq!(t.validate(), Err(TransformError::ZeroRotation));
        let mut t = Transform::IDENTITY;
        t.scale = [1.0, 0.0, 1.0];
        assert!(matches!(
            t.validate(),
            Err(TransformError::SingularScale(_))
        ));
    }
}
