//! A solid from the sizes a person types: its kind and its dimensions
//! (the edge lengths of its bounding box along its own x, y and z, as
//! Blender's N panel shows "Dimensions"). One mapping for every host, so
//! a host never spells out which size is a radius and which a height.
//!
//! | kind | from `[x, y, z]` |
//! | --- | --- |
//! | box | edge lengths `x, y, z` |
//! | sphere | radius `x / 2` |
//! | ellipsoid | semi-axes `x / 2, y / 2, z / 2` |
//! | cylinder, cone | radius `x / 2`, height `z` |
//! | torus | tube radius `z / 2`, major radius `x / 2 - z / 2` |
//! | capsule | radius `x / 2`, length between the caps' centres `z - x` |
//!
//! Round shapes take their diameter from `x` (`y` is not used), so a
//! host's one "Dimensions" field serves every kind. [`SolidShape::dimensions`]
//! is the inverse: `from_sizes(s.name(), s.dimensions())` gives `s` back
//! (up to rounding of the halving).

use super::{SolidError, SolidShape};

/// The solid kinds, as scripts spell them, in the order hosts list them.
pub const SOLID_KINDS: [&str; 7] = [
    "box",
    "sphere",
    "ellipsoid",
    "cylinder",
    "cone",
    "torus",
    "capsule",
];

impl SolidShape {
    /// The solid of kind `kind` (one of [`SOLID_KINDS`]) whose bounding box
    /// has the edge lengths `dimensions` (see the module doc), checked as
    /// [`Self::validate`] checks it.
    pub fn from_sizes(kind: &str, dimensions: [f64; 3]) -> Result<Self, SolidError> {
        let [x, y, z] = dimensions;
        let shape = match kind {
            "box" => Self::Box { size: dimensions },
            "sphere" => Self::Sphere { radius: x / 2.0 },
            "ellipsoid" => Self::Ellipsoid {
                radii: [x / 2.0, y / 2.0, z / 2.0],
            },
            "cylinder" => Self::Cylinder {
                radius: x / 2.0,
                height: z,
            },
            "cone" => Self::Cone {
                radius: x / 2.0,
                height: z,
            },
            "torus" => Self::Torus {
                major_radius: x / 2.0 - z / 2.0,
                minor_radius: z / 2.0,
            },
            "capsule" => Self::Capsule {
                radius: x / 2.0,
                length: z - x,
            },
            other => return Err(SolidError::UnknownKind(other.chars().take(40).collect())),
        };
        if kind == "torus" && x.is_finite() && z.is_finite() && z > 0.0 && x <= 2.0 * z {
            // The general check would name radii the person never typed.
            return Err(SolidError::TorusTooThin { outer: x, tube: z });
        }
        if kind == "capsule" && x.is_finite() && z.is_finite() && x > 0.0 && z < x {
            return Err(SolidError::CapsuleTooShort {
                diameter: x,
                length: z,
            });
        }
        shape.validate()?;
        Ok(shape)
    }

    /// The edge lengths of the shape's bounding box along its own axes:
    /// what [`Self::from_sizes`] takes.
    pub fn dimensions(&self) -> [f64; 3] {
        self.half_extents().map(|h| 2.0 * h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_round_trips_through_its_dimensions() {
        let dims = [0.3, 0.3, 0.1];
        for kind in SOLID_KINDS {
            let dims = if kind == "capsule" {
                [0.1, 0.1, 0.3]
            } else {
                dims
            };
            let s = SolidShape::from_sizes(kind, dims).unwrap();
            assert_eq!(s.name(), kind);
            let back = SolidShape::from_sizes(kind, s.dimensions()).unwrap();
            assert_eq!(back, s, "{kind}");
            let d = s.dimensions();
            // Round shapes: x and y are the diameter; z the height (a
            // sphere's is its diameter too).
            let z = if kind == "sphere" { dims[0] } else { dims[2] };
            assert!((d[0] - dims[0]).abs() < 1e-15, "{kind}: {d:?}");
            assert!((d[2] - z).abs() < 1e-15, "{kind}: {d:?}");
        }
    }

    #[test]
    fn sizes_name_their_meaning() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        assert_eq!(
            SolidShape::from_sizes("cylinder", [0.2, 0.2, 0.5]).unwrap(),
            SolidShape::Cylinder {
                radius: 0.1,
                height: 0.5
            }
        );
        match SolidShape::from_sizes("torus", [0.5, 0.5, 0.1]).unwrap() {
            SolidShape::Torus {
                major_radius,
                minor_radius,
            } => assert!(close(major_radius, 0.2) && close(minor_radius, 0.05)),
            other => panic!("{other:?}"),
        }
        match SolidShape::from_sizes("capsule", [0.1, 0.1, 0.3]).unwrap() {
            SolidShape::Capsule { radius, length } => {
                assert!(close(radius, 0.05) && close(length, 0.2))
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn bad_sizes_are_typed_errors_that_say_what_to_type() {
        let e = SolidShape::from_sizes("teapot", [1.0; 3]).unwrap_err();
        assert!(e.to_string().contains("box, sphere"), "{e}");
        let e = SolidShape::from_sizes("torus", [0.2, 0.2, 0.1]).unwrap_err();
        assert!(matches!(e, SolidError::TorusTooThin { .. }), "{e}");
        assert!(e.to_string().contains("twice"), "{e}");
        let e = SolidShape::from_sizes("capsule", [0.2, 0.2, 0.1]).unwrap_err();
        assert!(matches!(e, SolidError::CapsuleTooShort { .. }), "{e}");
        let e = SolidShape::from_sizes("box", [0.1, f64::NAN, 0.1]).unwrap_err();
        assert!(e.to_string().contains("size[1]"), "{e}");
        let e = SolidShape::from_sizes("sphere", [-1.0, 1.0, 1.0]).unwrap_err();
        assert!(e.to_string().contains("radius"), "{e}");
    }
}
