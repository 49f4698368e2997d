//! Key cross-sections (§3.1 eq. 1): a closed planar profile in the
//! section's local frame (templates circle, regular n-gon, rectangle,
//! ellipse, a sketched closed point loop, or any closed NURBS curve), its
//! spine parameter `v`, a uniform scale and a twist angle.
//!
//! Local frame: `x` along the RMF reference (the spine plane normal at the
//! first section), `y = tangent x x` (in the spine plane), `z` the spine
//! tangent. Profiles are counter-clockwise seen from `+z`; a sketched loop
//! given clockwise is reversed so the side surface normal `S_u x S_v` always
//! points outwards.

use glam::{DAffine3, DVec3};
use serde::{Deserialize, Serialize};

use super::GcError;
use crate::math::Frame;
use crate::nurbs::{interpolate_closed, shapes, NurbsCurve, ParamMethod};

/// Highest degree of a `Curve` section (every section is raised to the
/// highest degree present when lofting).
pub const MAX_CURVE_DEGREE: usize = 7;

/// The shape of a key section in its local frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "template", rename_all = "snake_case")]
pub enum Profile {
    /// Circle of radius `radius`.
    Circle {
        /// Radius.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        radius: f64,
    },
    /// Ellipse with semi-axes `rx` (local x) and `ry` (local y).
    Ellipse {
        /// Semi-axis along local x.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        rx: f64,
        /// Semi-axis along local y.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        ry: f64,
    },
    /// Regular polygon with `sides` vertices on the circle of `radius`.
    Polygon {
        /// Number of sides, at least 3.
        #[schemars(range(min = 3, max = 1024))]
        sides: u32,
        /// Circumradius.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        radius: f64,
    },
    /// Axis-aligned rectangle centered on the spine.
    Rectangle {
        /// Extent along local x.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        width: f64,
        /// Extent along local y.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        height: f64,
    },
    /// A closed loop of 2D points (a sketch), interpolated by a periodic
    /// cubic; the first point is not repeated.
    Points {
        /// Loop points in local (x, y).
        #[schemars(extend("x-unit" = "m"))]
        points: Vec<[f64; 2]>,
    },
    /// Any closed NURBS curve in local coordinates, domain `[0, 1]`,
    /// clamped, with `C(0) = C(1)` (e.g. an inserted iso-curve).
    Curve {
        /// The curve.
        curve: NurbsCurve,
    },
}

/// A key cross-section of a GC.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KeySection {
    /// Profile in the local frame.
    pub profile: Profile,
    /// Spine parameter of the section's center.
    pub v: f64,
    /// Uniform scale in the local frame (resize).
    pub scale: f64,
    /// Rotation about the local z axis, radians (twist).
    pub twist: f64,
}

fn positive(what: &'static str, x: f64) -> Result<(), GcError> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else if x.is_nan() || x.is_infinite() {
        Err(GcError::NonFinite(what))
    } else {
        Err(GcError::BadSize { what, value: x })
    }
}

/// Signed area of a closed 2D loop (positive when counter-clockwise).
pub fn signed_area(pts: &[[f64; 2]]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        * 0.5
}

/// True when two segments of the closed loop cross (non-adjacent ones).
pub fn loop_self_intersects(pts: &[[f64; 2]]) -> bool {
    let n = pts.len();
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        for j in i + 1..n {
            if j == i || (j + 1) % n == i || j == (i + 1) % n {
                continue;
            }
            let (c, d) = (pts[j], pts[(j + 1) % n]);
            let d1 = cross(a, b, c);
            let d2 = cross(a, b, d);
            let d3 = cross(c, d, a);
            let d4 = cross(c, d, b);
            if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
                && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
            {
                return true;
            }
        }
    }
    false
}

impl Profile {
    /// The profile as a closed clamped NURBS curve on `[0, 1]` in local
    /// coordinates, after validating its parameters.
    pub fn curve(&self) -> Result<NurbsCurve, GcError> {
        Ok(match self {
            Self::Circle { radius } => {
                positive("circle radius", *radius)?;
                shapes::ellipse(*radius, *radius)
            }
            Self::Ellipse { rx, ry } => {
                positive("ellipse rx", *rx)?;
                positive("ellipse ry", *ry)?;
                shapes::ellipse(*rx, *ry)
            }
            Self::Polygon { sides, radius } => {
                positive("polygon radius", *radius)?;
                if *sides < 3 {
                    return Err(GcError::TooFewSides(*sides));
                }
                if *sides > 1024 {
                    return Err(GcError::BadSize {
                        what: "polygon sides (at most 1024)",
                        value: *sides as f64,
                    });
                }
                shapes::regular_polygon(*sides as usize, *radius)?
            }
            Self::Rectangle { width, height } => {
                positive("rectangle width", *width)?;
                positive("rectangle height", *height)?;
                shapes::rectangle(*width, *height)?
            }
            Self::Points { points } => {
                if points.iter().flatten().any(|x| !x.is_finite()) {
                    return Err(GcError::NonFinite("section points"));
                }
                if points.len() < 3 {
                    return Err(GcError::DegenerateSection("fewer than 3 points"));
                }
                if points.len() > 4096 {
                    return Err(GcError::DegenerateSection("more than 4096 points"));
                }
                if loop_self_intersects(points) {
                    return Err(GcError::DegenerateSection("the loop intersects itself"));
                }
                let area = signed_area(points);
                let ext = points.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
                if !(area.abs() > 1e-12 * ext * ext) {
                    return Err(GcError::DegenerateSection("the loop encloses no area"));
                }
                let mut p3: Vec<DVec3> =
                    points.iter().map(|p| DVec3::new(p[0], p[1], 0.0)).collect();
                if area < 0.0 {
                    p3[1..].reverse();
                }
                interpolate_closed(&p3, ParamMethod::Centripetal)?
            }
            Self::Curve { curve } => {
                curve.validate()?;
                if curve.degree > MAX_CURVE_DEGREE || curve.control.len() > 4096 {
                    return Err(GcError::DegenerateSection(
                        "a curve section may have degree at most 7 and 4096 control points",
                    ));
                }
                if !curve.is_clamped() || curve.domain() != (0.0, 1.0) {
                    return Err(GcError::DegenerateSection(
                        "a curve section must be clamped on [0, 1]",
                    ));
                }
                let (a, b) = (curve.point(0.0), curve.point(1.0));
                if (a - b).length() > 1e-9 * (1.0 + a.length()) {
                    return Err(GcError::DegenerateSection("the curve is not closed"));
                }
                curve.clone()
            }
        })
    }
}

impl KeySection {
    /// A template section with unit scale and no twist.
    pub fn new(profile: Profile, v: f64) -> Self {
        Self {
            profile,
            v,
            scale: 1.0,
            twist: 0.0,
        }
    }

    /// Validates scale and twist.
    pub fn validate(&self) -> Result<(), GcError> {
        positive("section scale", self.scale)?;
        if !self.twist.is_finite() {
            return Err(GcError::NonFinite("section twist"));
        }
        if !self.v.is_finite() {
            return Err(GcError::NonFinite("section parameter"));
        }
        Ok(())
    }

    /// The local-to-world map of the section placed in `frame`:
    /// frame * rotation(twist) * scale.
    pub fn placement(&self, frame: &Frame) -> DAffine3 {
        let f = DAffine3::from_cols(frame.r, frame.s, frame.tangent, frame.origin);
        f * DAffine3::from_rotation_z(self.twist) * DAffine3::from_scale(DVec3::splat(self.scale))
    }

    /// The section curve in world space.
    pub fn world_curve(&self, frame: &Frame) -> Result<NurbsCurve, GcError> {
        Ok(self.profile.curve()?.transformed(&self.placement(frame)))
    }
}
