//! The GC ops' payloads (`gc_create`, `gc_bend`, ...): plain values with
//! every parameter explicit. The document layer (`doc::ops`) names the
//! assembly object and applies each to a copy of it; these values only
//! say what to do to which part and section.

use glam::DVec3;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{fit_spine, Gc, GcAssembly, GcError, KeySection, Profile, Resolution, ShapeType};
use crate::id::index_type;

index_type!(
    /// The index of a part in its assembly (parents come before children).
    /// Serialized as a plain number.
    PartId,
    "part",
    "A part of the assembly, by index (0 is the first part created)."
);

index_type!(
    /// The index of a key section along a GC's spine (0 is the first).
    /// Serialized as a plain number.
    SectionIndex,
    "section",
    "A key section, by index along the spine (0 is the first)."
);

fn default_scale() -> f64 {
    1.0
}

/// A key section as ops give it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SectionSpec {
    /// Profile in the local frame.
    pub profile: Profile,
    /// Spine parameter in `[0, 1]` (the created spine's domain).
    #[schemars(range(min = 0.0, max = 1.0))]
    pub v: f64,
    /// Uniform scale.
    #[serde(default = "default_scale")]
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub scale: f64,
    /// Twist angle, radians.
    #[serde(default)]
    #[schemars(extend("x-unit" = "rad"))]
    pub twist: f64,
}

fn default_shape() -> ShapeType {
    ShapeType::Solid
}

/// Create a one-part GC assembly: a spine through `spine` points (global
/// cubic interpolation, chord length, domain `[0, 1]`) in the plane with
/// normal `plane_normal`, and key sections at increasing `v`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GcCreate {
    /// Spine points (at least 2, coplanar).
    #[schemars(with = "Vec<[f64; 3]>", extend("x-unit" = "m"))]
    pub spine: Vec<DVec3>,
    /// Normal of the spine plane.
    #[schemars(with = "[f64; 3]")]
    pub plane_normal: DVec3,
    /// Key sections (2 to 256: see `gc::budget`).
    #[schemars(length(min = 2, max = 256))]
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
        build_gc(
            &self.spine,
            self.plane_normal,
            &self.sections,
            self.shape,
            self.resolution,
        )
    }
}

/// A GC whose spine interpolates `spine` (in the plane with normal
/// `plane_normal`) with key sections `sections`.
pub fn build_gc(
    spine: &[DVec3],
    plane_normal: DVec3,
    sections: &[SectionSpec],
    shape: ShapeType,
    resolution: Resolution,
) -> Result<Gc, GcError> {
    let spine = fit_spine(spine, plane_normal)?;
    let sections = sections
        .iter()
        .map(|s| KeySection {
            profile: s.profile.clone(),
            v: s.v,
            scale: s.scale,
            twist: s.twist,
        })
        .collect();
    Gc::new(spine, sections, shape, resolution)
}

/// An edit of one part's GC, without propagation to other parts.
pub trait GcEdit {
    /// The part edited.
    fn part(&self) -> PartId;
    /// Edits that part's GC.
    fn edit(&self, gc: &mut Gc) -> Result<(), GcError>;
}

/// Applies `edit` to its part of `asm`.
pub fn edit_part_gc(asm: &mut GcAssembly, edit: &impl GcEdit) -> Result<(), GcError> {
    edit.edit(&mut asm.part_mut(edit.part().0)?.gc)
}

macro_rules! gc_edit {
    ($(#[$doc:meta])* $name:ident { $($(#[$fdoc:meta])* $field:ident : $ty:ty),* $(,)? }, |$gc:ident, $op:ident| $body:expr) => {
        $(#[$doc])*
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            /// The part of the assembly.
            #[serde(default)]
            pub part: PartId,
            $($(#[$fdoc])* pub $field: $ty,)*
        }

        impl GcEdit for $name {
            fn part(&self) -> PartId {
                self.part
            }
            fn edit(&self, $gc: &mut Gc) -> Result<(), GcError> {
                let $op = self;
                $body
            }
        }
    };
}

gc_edit!(
    /// Bend: move key point `section` to `to` within the spine plane.
    GcBend {
        /// Section whose key point moves.
        section: SectionIndex,
        /// New key point position (in the spine plane).
        #[schemars(with = "[f64; 3]", extend("x-unit" = "m"))]
        to: DVec3,
    },
    |gc, op| gc.bend(op.section.0, op.to)
);

gc_edit!(
    /// Replace the spine by the curve through `points`.
    GcReplaceSpine {
        /// New spine points (coplanar).
        #[schemars(with = "Vec<[f64; 3]>", extend("x-unit" = "m"))]
        points: Vec<DVec3>,
        /// Normal of their plane.
        #[schemars(with = "[f64; 3]")]
        plane_normal: DVec3,
    },
    |gc, op| gc.replace_spine(&op.points, op.plane_normal)
);

gc_edit!(
    /// Resize: scale section `section` by `factor` in its local frame.
    GcResize {
        /// Section index.
        section: SectionIndex,
        /// Scale factor (> 0).
        #[schemars(extend("exclusiveMinimum" = 0.0))]
        factor: f64,
    },
    |gc, op| gc.resize(op.section.0, op.factor)
);

gc_edit!(
    /// Shift: move section `section` to spine parameter `v`, between its
    /// neighbours.
    GcShift {
        /// Section index.
        section: SectionIndex,
        /// New spine parameter.
        #[schemars(range(min = 0.0, max = 1.0))]
        v: f64,
    },
    |gc, op| gc.shift(op.section.0, op.v)
);

gc_edit!(
    /// Twist: rotate interior section `section` by `angle` radians,
    /// propagated linearly, first and last fixed.
    GcTwist {
        /// Section index (not the first or last).
        section: SectionIndex,
        /// Angle in radians.
        #[schemars(extend("x-unit" = "rad"))]
        angle: f64,
    },
    |gc, op| gc.twist(op.section.0, op.angle)
);

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

gc_edit!(
    /// Replace section `section` by `profile`, turned by `twist` in the
    /// section's plane (the angle a template was drawn at).
    GcReplaceSection {
        /// Section index.
        section: SectionIndex,
        /// New profile in the section's local frame.
        profile: Profile,
        /// Rotation of the new profile about the spine, radians.
        #[serde(default, skip_serializing_if = "is_zero")]
        #[schemars(extend("x-unit" = "rad"))]
        twist: f64,
    },
    |gc, op| gc.replace_section(op.section.0, op.profile.clone(), op.twist)
);

gc_edit!(
    /// Delete section `section` (at least two remain).
    GcDeleteSection {
        /// Section index.
        section: SectionIndex,
    },
    |gc, op| gc.delete_section(op.section.0)
);

gc_edit!(
    /// Insert a key section at spine parameter `v` (shape unchanged).
    GcInsertSection {
        /// Spine parameter strictly inside the GC.
        #[schemars(range(min = 0.0, max = 1.0))]
        v: f64,
    },
    |gc, op| gc.insert_section(op.v).map(|_| ())
);

gc_edit!(
    /// Set the shape type and thickness.
    GcSetShape {
        /// New shape type.
        shape: ShapeType,
    },
    |gc, op| gc.set_shape(op.shape)
);

gc_edit!(
    /// Set the mesh resolution.
    GcSetResolution {
        /// New resolution.
        resolution: Resolution,
    },
    |gc, op| gc.set_resolution(op.resolution)
);
