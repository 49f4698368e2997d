//! Brushes as distance fields with gradients (paper §4.2, §4.5).
//!
//! Analytic shapes are exact signed distances except the ellipsoid, whose
//! exact distance needs a root solve per point: it uses the standard
//! first-order bound `k0 (k0 - 1) / k1` (exact on the surface and along the
//! axes, within a few percent near it), with its gradient by central
//! differences, normalized. The grid brush samples a dense grid
//! ([`DistanceGrid`]) trilinearly; its gradient is the exact derivative of
//! the trilinear interpolant, normalized. Grids from closed meshes are
//! built by [`super::mesh_brush`] with the mesh-to-SDF code of `core::sdf`.
//!
//! A brush lives in its own frame: `d_world(x) = s · d_local(Rᵀ(x − p) / s)`
//! for brush position `p`, rotation `R` and brush scale `s` (separate from
//! the model's scale).

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::mesh_brush::MeshBrush;
use super::SculptError;

/// A dense grid of signed distances: value `(i, j, k)` sits at
/// `origin + step · (i, j, k)` and is stored at `i + dims[0]·(j + dims[1]·k)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DistanceGrid {
    /// Position of sample `(0, 0, 0)`.
    pub origin: [f64; 3],
    /// Spacing between samples (same on every axis).
    pub step: f64,
    /// Samples per axis, each at least 2.
    pub dims: [u32; 3],
    /// Signed distances, x fastest.
    pub values: Vec<f64>,
}

impl DistanceGrid {
    /// Samples `f` on the grid (for analytic fields and tests).
    pub fn sample(origin: [f64; 3], step: f64, dims: [u32; 3], f: impl Fn(DVec3) -> f64) -> Self {
        let o = DVec3::from_array(origin);
        let mut values = Vec::with_capacity(dims.iter().map(|&d| d as usize).product());
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    values.push(f(o + step * DVec3::new(i as f64, j as f64, k as f64)));
                }
            }
        }
        Self {
            origin,
            step,
            dims,
            values,
        }
    }

    fn validate(&self) -> Result<(), SculptError> {
        finite("brush.origin", &self.origin)?;
        positive("brush.step", self.step)?;
        let expected = self
            .dims
            .iter()
            .fold(1usize, |acc, &d| acc.saturating_mul(d as usize));
        if self.dims.iter().any(|&d| d < 2) || self.values.len() != expected {
            return Err(SculptError::BadGrid {
                dims: self.dims,
                expected,
                found: self.values.len(),
            });
        }
        if let Some(i) = self.values.iter().position(|v| !v.is_finite()) {
            return Err(SculptError::NonFinite {
                field: format!("brush.values[{i}]"),
                value: vec![self.values[i]],
            });
        }
        Ok(())
    }

    /// The radius, about the brush origin, of the grid's zero set (the
    /// brush's own surface): the farthest point where the distance
    /// crosses zero along a grid edge (linearly interpolated, as the
    /// trilinear field does along its edges), or a sample at or below
    /// zero on the grid's outer faces (an inside cut off by the box).
    /// 0 when no sample is at or below zero. One pass over the samples:
    /// strokes compute it once ([`BrushShape::size_radius`]).
    ///
    /// This, not the corner of the padded box, is the brush's size: the
    /// mesh brush of a sphere of radius `r` then has size `r` like the
    /// analytic sphere, and refines to the same edge length (issue 33:
    /// the box corner made mesh brushes refine about four times coarser).
    pub fn zero_set_radius(&self) -> f64 {
        let [nx, ny, nz] = self.dims.map(|d| d as usize);
        let o = DVec3::from_array(self.origin);
        let at =
            |i: usize, j: usize, k: usize| o + self.step * DVec3::new(i as f64, j as f64, k as f64);
        let mut r2 = 0.0f64;
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let v = self.at(i, j, k);
                    let inside = v <= 0.0;
                    if inside
                        && (i == 0 || j == 0 || k == 0 || i + 1 == nx || j + 1 == ny || k + 1 == nz)
                    {
                        r2 = r2.max(at(i, j, k).length_squared());
                    }
                    for (di, dj, dk) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                        let (a, b, c) = (i + di, j + dj, k + dk);
                        if a >= nx || b >= ny || c >= nz {
                            continue;
                        }
                        let w = self.at(a, b, c);
                        if inside == (w <= 0.0) {
                            continue;
                        }
                        // The crossing of the linear interpolant (v and w
                        // differ in sign, so v - w is not zero).
                        let t = (v / (v - w)).clamp(0.0, 1.0);
                        let p = at(i, j, k).lerp(at(a, b, c), t);
                        r2 = r2.max(p.length_squared());
                    }
                }
            }
        }
        r2.sqrt()
    }

    fn hi(&self) -> DVec3 {
        DVec3::from_array(self.origin)
            + self.step * DVec3::from_array(self.dims.map(|d| (d - 1) as f64))
    }

    #[inline]
    fn at(&self, i: usize, j: usize, k: usize) -> f64 {
        let [nx, ny, _] = self.dims.map(|d| d as usize);
        self.values[i + nx * (j + ny * k)]
    }

    /// Trilinear distance and normalized gradient. Outside the grid the
    /// value at the nearest grid point plus the distance to it is used.
    pub fn eval(&self, x: DVec3) -> (f64, DVec3) {
        let lo = DVec3::from_array(self.origin);
        let hi = self.hi();
        let xc = x.clamp(lo, hi);
        let outside = x - xc;
        let g = (xc - lo) / self.step;
        let n = self.dims.map(|d| d as usize - 2);
        let i = (g.x.floor() as usize).min(n[0]);
        let j = (g.y.floor() as usize).min(n[1]);
        let k = (g.z.floor() as usize).min(n[2]);
        let (tx, ty, tz) = (g.x - i as f64, g.y - j as f64, g.z - k as f64);
        let c = |a: usize, b: usize, e: usize| self.at(i + a, j + b, k + e);
        let (c000, c100, c010, c110) = (c(0, 0, 0), c(1, 0, 0), c(0, 1, 0), c(1, 1, 0));
        let (c001, c101, c011, c111) = (c(0, 0, 1), c(1, 0, 1), c(0, 1, 1), c(1, 1, 1));
        let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
        let x00 = lerp(c000, c100, tx);
        let x10 = lerp(c010, c110, tx);
        let x01 = lerp(c001, c101, tx);
        let x11 = lerp(c011, c111, tx);
        let y0 = lerp(x00, x10, ty);
        let y1 = lerp(x01, x11, ty);
        let d = lerp(y0, y1, tz);
        let dx = lerp(
            lerp(c100 - c000, c110 - c010, ty),
            lerp(c101 - c001, c111 - c011, ty),
            tz,
        );
        let dy = lerp(x10 - x00, x11 - x01, tz);
        let dz = y1 - y0;
        let grad = DVec3::new(dx, dy, dz) / self.step;
        let ol = outside.length();
        if ol > 0.0 {
            let dir = outside / ol;
            let g = (grad.normalize_or_zero() + dir).normalize_or(dir);
            return (d + ol, g);
        }
        (d, grad.normalize_or(DVec3::Z))
    }
}

/// A brush shape's size and query bound in its own frame (unscaled), see
/// [`BrushShape::extent`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrushExtent {
    /// [`BrushShape::size_radius`].
    pub size: f64,
    /// [`BrushShape::bound_radius`].
    pub bound: f64,
}

/// A brush shape as a distance field in the brush's own frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum BrushShape {
    /// A ball of `radius` around the brush position.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// An ellipsoid with semi-axes `radii` along the brush's x, y, z.
    Ellipsoid {
        /// Semi-axes.
        radii: [f64; 3],
    },
    /// A capsule along the brush's z axis.
    Capsule {
        /// Radius.
        radius: f64,
        /// Half the length of the core segment.
        half_length: f64,
    },
    /// A box with `half_extents` along the brush's axes.
    Box {
        /// Half sizes.
        half_extents: [f64; 3],
    },
    /// A sampled distance grid (in the brush frame).
    Grid(DistanceGrid),
    /// A grid generated from a closed mesh ([`MeshBrush`]). The
    /// `sculpt_stroke` op resolves it to [`Self::Grid`] before the stroke
    /// ([`MeshBrush::to_grid`]); left unresolved it reaches nothing
    /// (distance +infinity, bound radius 0).
    Mesh(MeshBrush),
}

fn finite(field: &str, v: &[f64]) -> Result<(), SculptError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(SculptError::NonFinite {
            field: field.into(),
            value: v.to_vec(),
        })
    }
}

pub(crate) fn positive(field: &str, x: f64) -> Result<(), SculptError> {
    finite(field, &[x])?;
    if x > 0.0 {
        Ok(())
    } else {
        Err(SculptError::NonPositive {
            field: field.into(),
            value: x,
        })
    }
}

pub(crate) fn check_finite(field: &str, v: &[f64]) -> Result<(), SculptError> {
    finite(field, v)
}

impl BrushShape {
    /// Checks every size is finite and positive and a grid is well formed.
    pub fn validate(&self) -> Result<(), SculptError> {
        match self {
            Self::Sphere { radius } => positive("brush.radius", *radius),
            Self::Ellipsoid { radii } => radii.iter().try_for_each(|&r| positive("brush.radii", r)),
            Self::Capsule {
                radius,
                half_length,
            } => {
                positive("brush.radius", *radius)?;
                finite("brush.half_length", &[*half_length])?;
                if *half_length < 0.0 {
                    return Err(SculptError::NonPositive {
                        field: "brush.half_length".into(),
                        value: *half_length,
                    });
                }
                Ok(())
            }
            Self::Box { half_extents } => half_extents
                .iter()
                .try_for_each(|&r| positive("brush.half_extents", r)),
            Self::Grid(g) => g.validate(),
            Self::Mesh(m) => m.validate(),
        }
    }

    /// [`Self::size_radius`] and [`Self::bound_radius`] together, with one
    /// pass over a grid's samples.
    pub fn extent(&self) -> BrushExtent {
        match self {
            Self::Grid(g) => {
                let size = g.zero_set_radius();
                BrushExtent {
                    size,
                    bound: size + g.step * 3f64.sqrt(),
                }
            }
            _ => {
                let r = self.bound_radius();
                BrushExtent { size: r, bound: r }
            }
        }
    }

    /// The brush's size: the radius, about the brush origin, of the ball
    /// its surface (distance 0) fits in. Edge lengths are relative to it
    /// (`max_edge_rel`), so two brushes of the same shape refine alike
    /// whether analytic or sampled. For a grid this is a pass over its
    /// samples ([`DistanceGrid::zero_set_radius`]): compute it once per
    /// stroke.
    pub fn size_radius(&self) -> f64 {
        self.extent().size
    }

    /// A radius around the brush origin outside which the distance is at
    /// least the distance to that ball (a bound for spatial queries). For
    /// analytic shapes this is their size; a grid's adds one cell
    /// diagonal to [`Self::size_radius`] (the trilinear zero set lies
    /// within a cell of its edge crossings). A pass over a grid's samples:
    /// compute it once per stroke.
    pub fn bound_radius(&self) -> f64 {
        match self {
            Self::Sphere { radius } => *radius,
            Self::Ellipsoid { radii } => radii.iter().fold(0.0f64, |a, &b| a.max(b)),
            Self::Capsule {
                radius,
                half_length,
            } => radius + half_length,
            Self::Box { half_extents } => DVec3::from_array(*half_extents).length(),
            Self::Grid(_) => self.extent().bound,
            Self::Mesh(_) => 0.0,
        }
    }

    /// Signed distance and unit gradient at `x` in the brush frame.
    pub fn eval(&self, x: DVec3) -> (f64, DVec3) {
        match self {
            Self::Sphere { radius } => {
                let l = x.length();
                (l - radius, if l > 0.0 { x / l } else { DVec3::Z })
            }
            Self::Ellipsoid { radii } => {
                let r = DVec3::from_array(*radii);
                let f = |p: DVec3| {
                    let k0 = (p / r).length();
                    let k1 = (p / (r * r)).length();
                    if k1 > 0.0 {
                        k0 * (k0 - 1.0) / k1
                    } else {
                        -r.min_element()
                    }
                };
                let e = 1e-6 * r.min_element();
                let g = DVec3::new(
                    f(x + DVec3::X * e) - f(x - DVec3::X * e),
                    f(x + DVec3::Y * e) - f(x - DVec3::Y * e),
                    f(x + DVec3::Z * e) - f(x - DVec3::Z * e),
                );
                (f(x), g.normalize_or(DVec3::Z))
            }
            Self::Capsule {
                radius,
                half_length,
            } => {
                let q = DVec3::new(0.0, 0.0, x.z.clamp(-half_length, *half_length));
                let v = x - q;
                let l = v.length();
                (l - radius, if l > 0.0 { v / l } else { DVec3::X })
            }
            Self::Box { half_extents } => {
                let b = DVec3::from_array(*half_extents);
                let q = x.abs() - b;
                let out = q.max(DVec3::ZERO);
                let ol = out.length();
                let sign = DVec3::new(sgn(x.x), sgn(x.y), sgn(x.z));
                if ol > 0.0 {
                    (ol, (out / ol) * sign)
                } else {
                    let m = q.max_element();
                    let axis = if q.x == m {
                        DVec3::X
                    } else if q.y == m {
                        DVec3::Y
                    } else {
                        DVec3::Z
                    };
                    (m, axis * sign)
                }
            }
            Self::Grid(g) => g.eval(x),
            Self::Mesh(_) => (f64::INFINITY, DVec3::Z),
        }
    }
}

#[inline]
fn sgn(x: f64) -> f64 {
    if x < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// A brush placed in model space: shape, position, rotation, scale.
#[derive(Clone, Copy, Debug)]
pub struct BrushPose {
    /// Brush origin.
    pub position: DVec3,
    /// Brush orientation (unit).
    pub rotation: DQuat,
    /// Brush scale (positive).
    pub scale: f64,
}

impl BrushPose {
    /// Signed distance and unit gradient of `shape` placed at this pose.
    #[inline]
    pub fn eval(&self, shape: &BrushShape, x: DVec3) -> (f64, DVec3) {
        let local = self.rotation.inverse() * (x - self.position) / self.scale;
        let (d, g) = shape.eval(local);
        (d * self.scale, self.rotation * g)
    }
}
