//! [`Gc`]: a generalized cylinder (§3.1): a planar spine, key sections
//! placed on it by rotation-minimizing frames, a shape type and a mesh
//! resolution. The surface is the exact skin through the placed sections
//! (eq. 2), natural cubic in `v` with the sections' spine parameters as
//! `v`-parameters, so that inserting an iso-curve keeps the surface.
//!
//! Frames: the RMF is propagated by double reflection over a fixed grid of
//! [`RMF_STEPS`] spine steps, starting from the spine plane normal; the
//! frame at a section's `v` is one more reflection step from the grid
//! sample below it. The frame at `v` therefore depends only on the spine
//! and `v`, never on the other sections, which keeps insert exact.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{budget, GcError, KeySection};
use crate::math::{rmf_step, Frame};
use crate::nurbs::{interpolate, skin, NurbsCurve, NurbsSurface, ParamMethod, SkinV};

/// Most points a spine may be interpolated through (the dense solve is
/// cubic in the count; sketched spines are simplified by RDP first).
pub const MAX_SPINE_POINTS: usize = 1024;

/// Double-reflection steps over the spine domain.
pub const RMF_STEPS: usize = 256;

/// The planar spine curve and its plane normal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spine {
    /// The spine (non-rational, in the plane).
    pub curve: NurbsCurve,
    /// Unit normal of the spine plane.
    pub plane_normal: DVec3,
}

/// The shape types of §3.1.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ShapeType {
    /// Side surface plus the faces enclosed by the first and last sections.
    Solid,
    /// The side surface thickened inwards by `thickness` (a pipe).
    Shell {
        /// Wall thickness τ.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        thickness: f64,
    },
    /// A shell plus a solid bottom (the face enclosed by the first section,
    /// `closed_end = start`) or top (`end`) thickened by `thickness`.
    Container {
        /// Wall and floor thickness τ.
        #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
        thickness: f64,
        /// Which end is closed.
        closed_end: ClosedEnd,
    },
}

/// The closed end of a container.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ClosedEnd {
    /// The first section's end (bottom).
    Start,
    /// The last section's end (top).
    End,
}

/// Mesh resolution: segments around a section (over the whole `u`
/// domain) and along the spine (over the sections' `v` range).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Resolution {
    /// Segments around each section.
    #[schemars(range(min = 4, max = 4096))]
    pub u: u32,
    /// Segments along the GC.
    #[schemars(range(min = 4, max = 4096))]
    pub v: u32,
}

impl Resolution {
    /// The default (print/export) resolution.
    pub const DEFAULT: Self = Self { u: 96, v: 64 };
    /// A VR preview resolution.
    pub const PREVIEW: Self = Self { u: 32, v: 24 };

    /// Checks the range 4..=4096.
    pub fn validate(&self) -> Result<(), GcError> {
        let ok = |x: u32| (4..=4096).contains(&x);
        if ok(self.u) && ok(self.v) {
            Ok(())
        } else {
            Err(GcError::BadResolution {
                u: self.u,
                v: self.v,
            })
        }
    }
}

impl Default for Resolution {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A generalized cylinder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Gc {
    /// The spine.
    pub spine: Spine,
    /// Key sections in increasing `v`.
    pub sections: Vec<KeySection>,
    /// Shape type.
    pub shape: ShapeType,
    /// Mesh resolution.
    pub resolution: Resolution,
}

/// Fits a spine through `points` (global cubic interpolation, chord
/// length; a line for two points) after checking that they are finite,
/// distinct and lie in the plane through the first with normal `normal`.
pub fn fit_spine(points: &[DVec3], normal: DVec3) -> Result<Spine, GcError> {
    if points.iter().any(|p| !p.is_finite()) || !normal.is_finite() {
        return Err(GcError::NonFinite("spine"));
    }
    if points.len() < 2 {
        return Err(GcError::ZeroLengthSpine);
    }
    if points.len() > MAX_SPINE_POINTS {
        return Err(GcError::BadSize {
            what: "spine point count (at most 1024; simplify the stroke first)",
            value: points.len() as f64,
        });
    }
    let n = normal.try_normalize().ok_or(GcError::ZeroPlaneNormal)?;
    let size = points
        .iter()
        .map(|p| (*p - points[0]).length())
        .fold(0.0, f64::max);
    if !(size > 1e-9) {
        return Err(GcError::ZeroLengthSpine);
    }
    for (i, p) in points.iter().enumerate() {
        let d = (*p - points[0]).dot(n).abs();
        if d > 1e-6 * size {
            return Err(GcError::NonPlanarSpine {
                index: i,
                distance: d,
            });
        }
    }
    let projected: Vec<DVec3> = points
        .iter()
        .map(|p| *p - n * (*p - points[0]).dot(n))
        .collect();
    if projected
        .windows(2)
        .any(|w| (w[1] - w[0]).length() <= 1e-12 * size)
    {
        return Err(GcError::ZeroLengthSpine);
    }
    let curve = interpolate(&projected, 3, ParamMethod::ChordLength)?;
    Ok(Spine {
        curve,
        plane_normal: n,
    })
}

/// The RMF grid of a spine: frames at `RMF_STEPS + 1` equally spaced
/// parameters.
#[derive(Clone, Debug)]
pub struct SpineFrames {
    a: f64,
    b: f64,
    frames: Vec<Frame>,
}

impl SpineFrames {
    /// Propagates frames along `spine` from the plane normal.
    pub fn new(spine: &Spine) -> Result<Self, GcError> {
        let (a, b) = spine.curve.domain();
        let mut frames: Vec<Frame> = Vec::with_capacity(RMF_STEPS + 1);
        for i in 0..=RMF_STEPS {
            let v = if i == RMF_STEPS {
                b
            } else {
                a + (b - a) * i as f64 / RMF_STEPS as f64
            };
            let d = spine.curve.derivatives(v, 1);
            let t = d[1].try_normalize().ok_or(GcError::DegenerateSpine(v))?;
            let f = match frames.last() {
                None => {
                    Frame::new(d[0], t, spine.plane_normal).ok_or(GcError::DegenerateSpine(v))?
                }
                Some(prev) => rmf_step(prev, d[0], t),
            };
            frames.push(f);
        }
        Ok(Self { a, b, frames })
    }

    /// The frame at `v` (one reflection step from the grid sample below).
    pub fn at(&self, spine: &Spine, v: f64) -> Result<Frame, GcError> {
        let x = ((v - self.a) / (self.b - self.a) * RMF_STEPS as f64).floor();
        let i = (x.max(0.0) as usize).min(RMF_STEPS);
        let d = spine.curve.derivatives(v, 1);
        let t = d[1].try_normalize().ok_or(GcError::DegenerateSpine(v))?;
        Ok(rmf_step(&self.frames[i], d[0], t))
    }
}

impl Gc {
    /// A GC after validation (sections, spine, shape, resolution; the mesh
    /// is checked when it is evaluated).
    pub fn new(
        spine: Spine,
        sections: Vec<KeySection>,
        shape: ShapeType,
        resolution: Resolution,
    ) -> Result<Self, GcError> {
        let gc = Self {
            spine,
            sections,
            shape,
            resolution,
        };
        gc.validate()?;
        Ok(gc)
    }

    /// Checks every parameter (not the meshability).
    pub fn validate(&self) -> Result<(), GcError> {
        self.spine.curve.validate()?;
        if !self.spine.plane_normal.is_finite() {
            return Err(GcError::NonFinite("spine plane normal"));
        }
        if self.spine.plane_normal.length_squared() == 0.0 {
            return Err(GcError::ZeroPlaneNormal);
        }
        self.resolution.validate()?;
        match self.shape {
            ShapeType::Solid => {}
            ShapeType::Shell { thickness } | ShapeType::Container { thickness, .. } => {
                if !thickness.is_finite() {
                    return Err(GcError::NonFinite("thickness"));
                }
                if thickness <= 0.0 {
                    return Err(GcError::BadSize {
                        what: "thickness",
                        value: thickness,
                    });
                }
            }
        }
        let k = self.sections.len();
        if k < 2 {
            return Err(GcError::TooFewSections { got: k });
        }
        let mut cost = budget::Cost::new(k, self.resolution)?;
        let (a, b) = self.spine.curve.domain();
        for (i, s) in self.sections.iter().enumerate() {
            s.validate()?;
            cost.add(&s.profile.curve()?)?;
            let lo = if i == 0 { a } else { self.sections[i - 1].v };
            let hi = if i + 1 == k {
                b
            } else {
                self.sections[i + 1].v
            };
            let ok_lo = if i == 0 { s.v >= lo } else { s.v > lo };
            let ok_hi = if i + 1 == k { s.v <= hi } else { s.v < hi };
            if !(ok_lo && ok_hi) {
                return Err(GcError::SectionOrder {
                    index: i,
                    v: s.v,
                    lo,
                    hi,
                });
            }
        }
        cost.finish().map(|_| ())
    }

    /// The frames along the spine.
    pub fn frames(&self) -> Result<SpineFrames, GcError> {
        SpineFrames::new(&self.spine)
    }

    /// The sections placed in world space, with their `v` parameters.
    pub fn placed_sections(&self) -> Result<(Vec<NurbsCurve>, Vec<f64>), GcError> {
        let frames = self.frames()?;
        let mut curves = Vec::with_capacity(self.sections.len());
        for s in &self.sections {
            curves.push(s.world_curve(&frames.at(&self.spine, s.v)?)?);
        }
        Ok((curves, self.sections.iter().map(|s| s.v).collect()))
    }

    /// The lofted side surface `S(u, v)` through the placed sections.
    pub fn surface(&self) -> Result<NurbsSurface, GcError> {
        self.validate()?;
        let (curves, vs) = self.placed_sections()?;
        Ok(skin(&curves, &vs, SkinV::NaturalCubic)?)
    }

    /// Key points `A(v_k)` on the spine.
    pub fn key_points(&self) -> Vec<DVec3> {
        self.sections
            .iter()
            .map(|s| self.spine.curve.point(s.v))
            .collect()
    }
}
