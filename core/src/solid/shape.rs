//! The solid shapes, their parameters and analytic measures.

use crate::math::fm::DetMath as _;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Segments around a circle when a script does not say; chosen so that
/// every shape's mesh volume is within 0.5% of its analytic volume.
pub const DEFAULT_SEGMENTS: u32 = 64;
/// Fewest segments around a circle.
pub const MIN_SEGMENTS: u32 = 8;
/// Most segments around a circle (keeps a typo from asking for a billion
/// triangles).
pub const MAX_SEGMENTS: u32 = 1024;

/// A solid centred on the origin; round shapes have their axis along +Z.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum SolidShape {
    /// Axis-aligned box with edge lengths `size`.
    Box {
        /// Edge lengths along x, y, z.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        size: [f64; 3],
    },
    /// Sphere.
    Sphere {
        /// Radius.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        radius: f64,
    },
    /// Ellipsoid with semi-axes along x, y, z.
    Ellipsoid {
        /// Semi-axes.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        radii: [f64; 3],
    },
    /// Closed cylinder from z = -height/2 to +height/2.
    Cylinder {
        /// Radius.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        radius: f64,
        /// Height along z.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        height: f64,
    },
    /// Cone with its base at z = -height/2 and apex at +height/2.
    Cone {
        /// Base radius.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        radius: f64,
        /// Height along z.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        height: f64,
    },
    /// Torus around the z axis.
    Torus {
        /// Distance from the axis to the tube centre.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        major_radius: f64,
        /// Tube radius; must be smaller than `major_radius`.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        minor_radius: f64,
    },
    /// Capsule: a cylinder of `length` capped by hemispheres.
    Capsule {
        /// Radius.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        radius: f64,
        /// Distance between the hemisphere centres (may be 0: a sphere).
        #[schemars(extend("x-unit" = "m"), range(min = 0.0))]
        length: f64,
    },
}

/// What is wrong with a solid's parameters.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolidError {
    /// A size must be a finite number above zero.
    #[error("{shape} {field} must be finite and > 0, got {value}")]
    NonPositive {
        /// Shape name.
        shape: &'static str,
        /// Parameter name.
        field: &'static str,
        /// The value given.
        value: f64,
    },
    /// A length that may be zero is negative or not finite.
    #[error("{shape} {field} must be finite and >= 0, got {value}")]
    Negative {
        /// Shape name.
        shape: &'static str,
        /// Parameter name.
        field: &'static str,
        /// The value given.
        value: f64,
    },
    /// A torus tube as thick as its ring would self-intersect.
    #[error("torus minor_radius {minor} must be smaller than major_radius {major}, or the tube self-intersects")]
    TorusSelfIntersects {
        /// Major radius.
        major: f64,
        /// Minor radius.
        minor: f64,
    },
    /// Resolution outside the supported range.
    #[error("segments must be within {MIN_SEGMENTS}..={MAX_SEGMENTS}, got {0}")]
    Segments(u32),
    /// [`SolidShape::from_sizes`] was given a kind that is not a solid.
    #[error("`{0}` is not a solid kind; use one of box, sphere, ellipsoid, cylinder, cone, torus, capsule")]
    UnknownKind(String),
    /// A torus's outer diameter must be more than twice its tube's
    /// diameter, or the tube fills the hole and meets itself.
    #[error("torus: the outer diameter {outer} must be more than twice the tube diameter {tube} (z); make x larger or z smaller")]
    TorusTooThin {
        /// Outer diameter (x).
        outer: f64,
        /// Tube diameter (z).
        tube: f64,
    },
    /// A capsule is at least as long as it is wide (its two caps).
    #[error("capsule: the length {length} (z) must be at least the diameter {diameter} (x); make z larger")]
    CapsuleTooShort {
        /// Diameter (x).
        diameter: f64,
        /// Length, caps included (z).
        length: f64,
    },
}

fn positive(shape: &'static str, field: &'static str, value: f64) -> Result<(), SolidError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SolidError::NonPositive {
            shape,
            field,
            value,
        })
    }
}

impl SolidShape {
    /// The shape's name as scripts spell it.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Box { .. } => "box",
            Self::Sphere { .. } => "sphere",
            Self::Ellipsoid { .. } => "ellipsoid",
            Self::Cylinder { .. } => "cylinder",
            Self::Cone { .. } => "cone",
            Self::Torus { .. } => "torus",
            Self::Capsule { .. } => "capsule",
        }
    }

    /// Checks that every size is finite and positive.
    pub fn validate(&self) -> Result<(), SolidError> {
        let s = self.name();
        match *self {
            Self::Box { size } => {
                for (f, v) in ["size[0]", "size[1]", "size[2]"].into_iter().zip(size) {
                    positive(s, f, v)?;
                }
            }
            Self::Sphere { radius } => positive(s, "radius", radius)?,
            Self::Ellipsoid { radii } => {
                for (f, v) in ["radii[0]", "radii[1]", "radii[2]"].into_iter().zip(radii) {
                    positive(s, f, v)?;
                }
            }
            Self::Cylinder { radius, height } | Self::Cone { radius, height } => {
                positive(s, "radius", radius)?;
                positive(s, "height", height)?;
            }
            Self::Torus {
                major_radius,
                minor_radius,
            } => {
                positive(s, "major_radius", major_radius)?;
                positive(s, "minor_radius", minor_radius)?;
                if minor_radius >= major_radius {
                    return Err(SolidError::TorusSelfIntersects {
                        major: major_radius,
                        minor: minor_radius,
                    });
                }
            }
            Self::Capsule { radius, length } => {
                positive(s, "radius", radius)?;
                if !(length.is_finite() && length >= 0.0) {
                    return Err(SolidError::Negative {
                        shape: s,
                        field: "length",
                        value: length,
                    });
                }
            }
        }
        Ok(())
    }

    /// The exact volume of the ideal (not tessellated) shape.
    pub fn analytic_volume(&self) -> f64 {
        match *self {
            Self::Box { size } => size[0] * size[1] * size[2],
            Self::Sphere { radius } => 4.0 / 3.0 * PI * radius.fpowi(3),
            Self::Ellipsoid { radii } => 4.0 / 3.0 * PI * radii[0] * radii[1] * radii[2],
            Self::Cylinder { radius, height } => PI * radius * radius * height,
            Self::Cone { radius, height } => PI * radius * radius * height / 3.0,
            Self::Torus {
                major_radius,
                minor_radius,
            } => 2.0 * PI * PI * major_radius * minor_radius * minor_radius,
            Self::Capsule { radius, length } => {
                PI * radius * radius * length + 4.0 / 3.0 * PI * radius.fpowi(3)
            }
        }
    }

    /// Half extents of the shape's bounding box.
    pub fn half_extents(&self) -> [f64; 3] {
        match *self {
            Self::Box { size } => size.map(|x| x / 2.0),
            Self::Sphere { radius } => [radius; 3],
            Self::Ellipsoid { radii } => radii,
            Self::Cylinder { radius, height } | Self::Cone { radius, height } => {
                [radius, radius, height / 2.0]
            }
            Self::Torus {
                major_radius,
                minor_radius,
            } => {
                let r = major_radius + minor_radius;
                [r, r, minor_radius]
            }
            Self::Capsule { radius, length } => [radius, radius, length / 2.0 + radius],
        }
    }
}
