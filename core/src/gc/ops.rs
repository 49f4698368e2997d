//! The GC ops (`gc_create`, `gc_bend`, ...): payloads with every parameter
//! explicit, and how each applies to a document. Every edit names the
//! assembly object and the part; the GC is edited on a copy, re-meshed,
//! and stored only when both succeed.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{fit_spine, Gc, GcAssembly, GcError, KeySection, Profile, Resolution, ShapeType};
use crate::doc::{Document, ObjectId, ObjectKind, OpError, OpOutcome};

fn default_scale() -> f64 {
    1.0
}

/// A key section as ops give it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionSpec {
    /// Profile in the local frame.
    pub profile: Profile,
    /// Spine parameter in `[0, 1]` (the created spine's domain).
    pub v: f64,
    /// Uniform scale.
    #[serde(default = "default_scale")]
    pub scale: f64,
    /// Twist angle, radians.
    #[serde(default)]
    pub twist: f64,
}

fn default_shape() -> ShapeType {
    ShapeType::Solid
}

/// Create a one-part GC assembly: a spine through `spine` points (global
/// cubic interpolation, chord length, domain `[0, 1]`) in the plane with
/// normal `plane_normal`, and key sections at increasing `v`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GcCreate {
    /// Spine points (at least 2, coplanar).
    pub spine: Vec<DVec3>,
    /// Normal of the spine plane.
    pub plane_normal: DVec3,
    /// Key sections (at least 2).
    pub sections: Vec<SectionSpec>,
    /// Shape type.
    #[serde(default = "default_shape")]
    pub shape: ShapeType,
    /// Mesh resolution.
    #[serde(default)]
    pub resolution: Resolution,
}

impl GcCreate {
    /// The GC this op describes.
    pub fn build(&self) -> Result<Gc, GcError> {
        let spine = fit_spine(&self.spine, self.plane_normal)?;
        let sections = self
            .sections
            .iter()
            .map(|s| KeySection {
                profile: s.profile.clone(),
                v: s.v,
                scale: s.scale,
                twist: s.twist,
            })
            .collect();
        Gc::new(spine, sections, self.shape, self.resolution)
    }

    /// Applies the op.
    pub fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        let gc = self.build()?;
        let id = doc.insert(ObjectKind::GcAssembly(GcAssembly::single(gc)))?;
        Ok(OpOutcome { created: Some(id) })
    }
}

fn edit(
    doc: &mut Document,
    id: ObjectId,
    part: usize,
    op: &'static str,
    f: impl FnOnce(&mut Gc) -> Result<(), GcError>,
) -> Result<OpOutcome, OpError> {
    let mut asm = match &doc.get(id)?.kind {
        ObjectKind::GcAssembly(a) => a.clone(),
        #[allow(unreachable_patterns)]
        other => {
            return Err(OpError::WrongKind {
                id,
                op,
                expected: "gc_assembly",
                found: other.name(),
            })
        }
    };
    f(&mut asm.part_mut(part)?.gc)?;
    doc.replace(id, ObjectKind::GcAssembly(asm))?;
    Ok(OpOutcome::default())
}

macro_rules! gc_edit_op {
    ($(#[$doc:meta])* $name:ident, $opname:literal, { $($(#[$fdoc:meta])* $field:ident : $ty:ty),* $(,)? }, |$gc:ident, $op:ident| $body:expr) => {
        $(#[$doc])*
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            /// The GC assembly object.
            pub id: ObjectId,
            /// The part of the assembly.
            #[serde(default)]
            pub part: usize,
            $($(#[$fdoc])* pub $field: $ty,)*
        }

        impl $name {
            /// Applies the op.
            pub fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
                let $op = self;
                edit(doc, self.id, self.part, $opname, |$gc: &mut Gc| $body)
            }
        }
    };
}

gc_edit_op!(
    /// Bend: move key point `section` to `to` within the spine plane.
    GcBend, "gc_bend", {
        /// Section whose key point moves.
        section: usize,
        /// New key point position (in the spine plane).
        to: DVec3,
    },
    |gc, op| gc.bend(op.section, op.to)
);

gc_edit_op!(
    /// Replace the spine by the curve through `points`.
    GcReplaceSpine, "gc_replace_spine", {
        /// New spine points (coplanar).
        points: Vec<DVec3>,
        /// Normal of their plane.
        plane_normal: DVec3,
    },
    |gc, op| gc.replace_spine(&op.points, op.plane_normal)
);

gc_edit_op!(
    /// Resize: scale section `section` by `factor` in its local frame.
    GcResize, "gc_resize", {
        /// Section index.
        section: usize,
        /// Scale factor (> 0).
        factor: f64,
    },
    |gc, op| gc.resize(op.section, op.factor)
);

gc_edit_op!(
    /// Shift: move section `section` to spine parameter `v`, between its
    /// neighbours.
    GcShift, "gc_shift", {
        /// Section index.
        section: usize,
        /// New spine parameter.
        v: f64,
    },
    |gc, op| gc.shift(op.section, op.v)
);

gc_edit_op!(
    /// Twist: rotate interior section `section` by `angle` radians,
    /// propagated linearly, first and last fixed.
    GcTwist, "gc_twist", {
        /// Section index (not the first or last).
        section: usize,
        /// Angle in radians.
        angle: f64,
    },
    |gc, op| gc.twist(op.section, op.angle)
);

gc_edit_op!(
    /// Replace section `section` by `profile`.
    GcReplaceSection, "gc_replace_section", {
        /// Section index.
        section: usize,
        /// New profile in the section's local frame.
        profile: Profile,
    },
    |gc, op| gc.replace_section(op.section, op.profile.clone())
);

gc_edit_op!(
    /// Delete section `section` (at least two remain).
    GcDeleteSection, "gc_delete_section", {
        /// Section index.
        section: usize,
    },
    |gc, op| gc.delete_section(op.section)
);

gc_edit_op!(
    /// Insert a key section at spine parameter `v` (shape unchanged).
    GcInsertSection, "gc_insert_section", {
        /// Spine parameter strictly inside the GC.
        v: f64,
    },
    |gc, op| gc.insert_section(op.v).map(|_| ())
);

gc_edit_op!(
    /// Set the shape type and thickness.
    GcSetShape, "gc_set_shape", {
        /// New shape type.
        shape: ShapeType,
    },
    |gc, op| gc.set_shape(op.shape)
);

gc_edit_op!(
    /// Set the mesh resolution.
    GcSetResolution, "gc_set_resolution", {
        /// New resolution.
        resolution: Resolution,
    },
    |gc, op| gc.set_resolution(op.resolution)
);
