//! The edits of §3.2 as methods on [`Gc`]. Each validates its input and
//! leaves `self` unchanged on error (edits work on a copy and commit at
//! the end); the caller re-meshes.

use glam::{DAffine3, DVec3};

use super::{fit_spine, Gc, GcError, KeySection, Profile, Resolution, ShapeType};
use crate::nurbs::interpolate_natural_cubic;

fn finite3(p: DVec3, what: &'static str) -> Result<(), GcError> {
    if p.is_finite() {
        Ok(())
    } else {
        Err(GcError::NonFinite(what))
    }
}

impl Gc {
    fn check_index(&self, index: usize) -> Result<(), GcError> {
        if index < self.sections.len() {
            Ok(())
        } else {
            Err(GcError::BadSection {
                index,
                count: self.sections.len(),
            })
        }
    }

    fn commit(&mut self, next: Gc) -> Result<(), GcError> {
        next.validate()?;
        *self = next;
        Ok(())
    }

    /// Bending: moves key point `A(v_index)` to `to` (which must lie in the
    /// spine plane), re-interpolates the spine through the key points at
    /// the sections' parameters (natural cubic), so sections are re-framed
    /// by the RMF of the new spine and re-lofted.
    pub fn bend(&mut self, index: usize, to: DVec3) -> Result<(), GcError> {
        self.check_index(index)?;
        finite3(to, "bend target")?;
        let mut keys = self.key_points();
        let n = self.spine.plane_normal.normalize();
        let off = (to - keys[index]).dot(n);
        let scale = keys
            .iter()
            .map(|k| (*k - keys[0]).length())
            .fold(1e-9, f64::max);
        if off.abs() > 1e-6 * scale {
            return Err(GcError::OffPlane {
                distance: off.abs(),
            });
        }
        keys[index] = to - n * off;
        if keys
            .windows(2)
            .any(|w| (w[1] - w[0]).length() <= 1e-12 * scale)
        {
            return Err(GcError::ZeroLengthSpine);
        }
        let vs: Vec<f64> = self.sections.iter().map(|s| s.v).collect();
        let mut next = self.clone();
        next.spine.curve = interpolate_natural_cubic(&keys, &vs)?;
        self.commit(next)
    }

    /// Replaces the spine by the curve through `points` (in a plane with
    /// normal `plane_normal`); the sections keep their relative positions,
    /// spread over the new spine's whole domain.
    pub fn replace_spine(&mut self, points: &[DVec3], plane_normal: DVec3) -> Result<(), GcError> {
        let spine = fit_spine(points, plane_normal)?;
        let (a, b) = spine.curve.domain();
        let k = self.sections.len();
        let (v0, v1) = (self.sections[0].v, self.sections[k - 1].v);
        let mut next = self.clone();
        for (i, s) in next.sections.iter_mut().enumerate() {
            s.v = if i == 0 {
                a
            } else if i + 1 == k {
                b
            } else {
                a + (b - a) * (s.v - v0) / (v1 - v0)
            };
        }
        next.spine = spine;
        self.commit(next)
    }

    /// Resizing: scales section `index` uniformly in its local frame.
    pub fn resize(&mut self, index: usize, factor: f64) -> Result<(), GcError> {
        self.check_index(index)?;
        if !factor.is_finite() {
            return Err(GcError::NonFinite("resize factor"));
        }
        if factor <= 0.0 {
            return Err(GcError::BadSize {
                what: "resize factor",
                value: factor,
            });
        }
        let mut next = self.clone();
        next.sections[index].scale *= factor;
        self.commit(next)
    }

    /// Shifting: moves section `index` along the spine to `v`, which must
    /// stay strictly between its neighbours' parameters (section order is
    /// kept); the section is re-oriented by the frame at `v`.
    pub fn shift(&mut self, index: usize, v: f64) -> Result<(), GcError> {
        self.check_index(index)?;
        if !v.is_finite() {
            return Err(GcError::NonFinite("shift parameter"));
        }
        let mut next = self.clone();
        next.sections[index].v = v;
        self.commit(next)
    }

    /// Twisting: rotates section `index` by `angle` (radians) about its
    /// local z axis and propagates the rotation linearly in `v` to the
    /// other sections, the first and last staying fixed.
    pub fn twist(&mut self, index: usize, angle: f64) -> Result<(), GcError> {
        self.check_index(index)?;
        if !angle.is_finite() {
            return Err(GcError::NonFinite("twist angle"));
        }
        let k = self.sections.len();
        if index == 0 || index + 1 == k {
            return Err(GcError::EndSectionFixed(index));
        }
        let v0 = self.sections[0].v;
        let vh = self.sections[index].v;
        let v1 = self.sections[k - 1].v;
        let mut next = self.clone();
        for (i, s) in next.sections.iter_mut().enumerate() {
            if i == 0 || i + 1 == k {
                continue;
            }
            let w = if i <= index {
                (s.v - v0) / (vh - v0)
            } else {
                (v1 - s.v) / (v1 - vh)
            };
            s.twist += angle * w;
        }
        self.commit(next)
    }

    /// Replacing a section: `profile` (in the section's local frame) takes
    /// the place of section `index`, with unit scale, turned by `twist`
    /// (radians; 0 for a profile given as it should lie).
    pub fn replace_section(
        &mut self,
        index: usize,
        profile: Profile,
        twist: f64,
    ) -> Result<(), GcError> {
        self.check_index(index)?;
        profile.curve()?;
        if !twist.is_finite() {
            return Err(GcError::NonFinite("section twist"));
        }
        let mut next = self.clone();
        let v = next.sections[index].v;
        next.sections[index] = KeySection {
            twist,
            ..KeySection::new(profile, v)
        };
        self.commit(next)
    }

    /// Deleting section `index`; at least two sections remain.
    pub fn delete_section(&mut self, index: usize) -> Result<(), GcError> {
        self.check_index(index)?;
        if self.sections.len() <= 2 {
            return Err(GcError::TooFewSections {
                got: self.sections.len() - 1,
            });
        }
        let mut next = self.clone();
        next.sections.remove(index);
        self.commit(next)
    }

    /// Insertion: a new key section at `v` (strictly between the first and
    /// last sections and different from every section's) is the iso-curve
    /// `S(u, v)` expressed in the frame at `A(v)`. The surface is unchanged
    /// (see the module doc of [`crate::gc`]). Returns the new index.
    pub fn insert_section(&mut self, v: f64) -> Result<usize, GcError> {
        if !v.is_finite() {
            return Err(GcError::NonFinite("insert parameter"));
        }
        let k = self.sections.len();
        let index = self.sections.iter().position(|s| s.v >= v).unwrap_or(k);
        if index == 0 || index == k || self.sections[index].v == v {
            let (lo, hi) = (self.sections[0].v, self.sections[k - 1].v);
            return Err(GcError::SectionOrder { index, v, lo, hi });
        }
        let surf = self.surface()?;
        let frame = self.frames()?.at(&self.spine, v)?;
        let iso = surf.iso_curve_v(v);
        let f = DAffine3::from_cols(frame.r, frame.s, frame.tangent, frame.origin);
        let local = iso.transformed(&f.inverse());
        let mut next = self.clone();
        next.sections
            .insert(index, KeySection::new(Profile::Curve { curve: local }, v));
        self.commit(next)?;
        Ok(index)
    }

    /// Sets the shape type (and thickness).
    pub fn set_shape(&mut self, shape: ShapeType) -> Result<(), GcError> {
        let mut next = self.clone();
        next.shape = shape;
        self.commit(next)
    }

    /// Sets the mesh resolution.
    pub fn set_resolution(&mut self, resolution: Resolution) -> Result<(), GcError> {
        let mut next = self.clone();
        next.resolution = resolution;
        self.commit(next)
    }
}
