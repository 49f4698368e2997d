//! Every op, declared once, and how each applies to a [`Document`].
//!
//! The table in this file is the op vocabulary: one line per op gives its
//! wire name, its Rust variant and payload type, and (through the payload's
//! declaration) its serde form and its schema (fields, types, units, ranges,
//! defaults, docs; see [`super::schema`]). Adding an op is: its payload type
//! (a plain value, in the geometry module it belongs to), one line here, its
//! apply (an [`ObjectEdit`], [`ObjectCreate`] or [`Apply`] impl in the
//! domain file below), and its tests. Both hosts read the schema, so they
//! see the new op without an edit.
//!
//! Three shapes of op:
//! - **edits of one object**, [`Edit<T>`]: the document layer owns the id
//!   field and the "object of kind K, or a typed error" lookup; `T` is a
//!   geometry value (e.g. [`crate::gc::GcBend`]) whose fields are the
//!   op's other fields, and its [`ObjectEdit`] impl calls the geometry code
//!   on a copy of the object (stored only when the edit succeeded);
//! - **creations**, [`Create<T>`]: `T` builds a new object kind;
//! - **document ops** (placement, duplicate, delete, rename): their own
//!   payloads in [`object`].
//!
//! Geometry modules never import `doc`: they take values and return values
//! or their own errors (the arrow points from here down to them).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{Document, OpError};

mod apply;
mod gc;
pub mod object;
mod print;
mod sculpt;
mod sdf;
pub mod solid;
mod styling;

pub use apply::{Apply, Create, Edit, EditCx, ObjectCreate, ObjectEdit, OpOutcome};
pub use object::{Delete, Duplicate, RenameObject, ReserveIds, SetTransform, TransformBy};
pub use solid::{AddSolid, EditSolid};

/// Declares the op table: the [`Op`] enum (serde tag `"op"`), [`OP_NAMES`],
/// [`Op::name`], [`Op::kind`] and [`Op::apply`], from one line per op.
macro_rules! ops {
    ($( $(#[$doc:meta])* $name:literal => $variant:ident($ty:ty), )*) => {
        /// One change to a document: a plain serde value with every
        /// parameter explicit. On the wire a JSON object whose `"op"` field
        /// names the op, e.g. `{"op":"add_solid","shape":{"kind":"sphere","radius":0.5}}`.
        /// Fields with defaults may be left out of scripts; the log always
        /// records them, so a recorded op never depends on defaults that may
        /// change.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
        #[serde(tag = "op")]
        pub enum Op {
            $( $(#[$doc])* #[serde(rename = $name)] $variant($ty), )*
        }

        /// The `"op"` names of every op, in table order.
        pub const OP_NAMES: &[&str] = &[$($name),*];

        /// `(name, kind)` of every op, in table order: the object kind each
        /// acts on (`"document"` for ops on any object, `"session"` for the
        /// ops no person writes: a shared session does).
        pub const OP_KINDS: &[(&str, &str)] = &[$(($name, <$ty as Apply>::KIND)),*];

        impl Op {
            /// The op's `"op"` name.
            pub fn name(&self) -> &'static str {
                match self { $(Self::$variant(_) => $name,)* }
            }

            /// The object kind the op acts on, or `"document"`.
            pub fn kind(&self) -> &'static str {
                match self { $(Self::$variant(_) => <$ty as Apply>::KIND,)* }
            }

            /// Applies the op to `doc`. On error `doc` may be partly changed:
            /// call through [`super::OpLog::apply`], which applies to a copy.
            pub fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
                let result = match self { $(Self::$variant(op) => op.apply(doc),)* };
                result.map_err(|e| e.in_op(self.name()))
            }
        }
    };
}

use crate::{assembly as asm, gc as g, print as pr, sculpt as sc, sdf as sd, styling as st};

ops! {
    /// Create a parametric solid.
    "add_solid" => AddSolid(AddSolid),
    /// Change a solid's shape or resolution.
    "edit_solid" => EditSolid(Edit<EditSolid>),
    /// Replace an object's placement (any kind).
    "set_transform" => SetTransform(SetTransform),
    /// Apply a transform on top of an object's placement (any kind).
    "transform_by" => TransformBy(TransformBy),
    /// Copy an object under a new id.
    "duplicate" => Duplicate(Duplicate),
    /// Delete an object. Its id is never reused.
    "delete" => Delete(Delete),
    /// Create a generalized-cylinder assembly with one part.
    "gc_create" => GcCreate(Create<g::GcCreate>),
    /// Bend a GC's spine by moving a key point.
    "gc_bend" => GcBend(Edit<g::GcBend>),
    /// Replace a GC's spine.
    "gc_replace_spine" => GcReplaceSpine(Edit<g::GcReplaceSpine>),
    /// Resize a key section.
    "gc_resize" => GcResize(Edit<g::GcResize>),
    /// Shift a key section along the spine.
    "gc_shift" => GcShift(Edit<g::GcShift>),
    /// Twist a key section (propagated linearly).
    "gc_twist" => GcTwist(Edit<g::GcTwist>),
    /// Replace a key section.
    "gc_replace_section" => GcReplaceSection(Edit<g::GcReplaceSection>),
    /// Delete a key section.
    "gc_delete_section" => GcDeleteSection(Edit<g::GcDeleteSection>),
    /// Insert a key section (shape unchanged).
    "gc_insert_section" => GcInsertSection(Edit<g::GcInsertSection>),
    /// Set a GC's shape type and thickness.
    "gc_set_shape" => GcSetShape(Edit<g::GcSetShape>),
    /// Set a GC's mesh resolution.
    "gc_set_resolution" => GcSetResolution(Edit<g::GcSetResolution>),
    /// Create a sculpt object from a base shape or a closed mesh.
    "sculpt_create" => SculptCreate(Create<sc::SculptCreate>),
    /// Apply one warp-brush stroke to a sculpt object.
    "sculpt_stroke" => SculptStroke(Edit<sc::SculptStroke>),
    /// Create an empty SDF volume.
    "sdf_create" => SdfCreate(Create<sd::SdfCreate>),
    /// Queue a library component as the next CSG operand.
    "sdf_add_operand" => SdfAddOperand(Edit<sd::SdfAddOperand>),
    /// Replace a pending operand's placement.
    "sdf_set_operand_transform" => SdfSetOperandTransform(Edit<sd::SdfSetOperandTransform>),
    /// Scale a pending operand by the two-hand ratio.
    "sdf_scale_two_hand" => SdfScaleTwoHand(Edit<sd::SdfScaleTwoHand>),
    /// Remove one pending operand.
    "sdf_cancel_operand" => SdfCancelOperand(Edit<sd::SdfCancelOperand>),
    /// Queue a copy of a pending operand under a new placement.
    "sdf_copy_operand" => SdfCopyOperand(Edit<sd::SdfCopyOperand>),
    /// Fuse every pending operand and extract the surface once.
    "sdf_update" => SdfUpdate(Edit<sd::SdfUpdate>),
    /// Add a closed mesh to the volume's components.
    "sdf_import_component" => SdfImportComponent(Edit<sd::SdfImportComponent>),
    /// Change the grid step (re-fuses everything).
    "sdf_set_step" => SdfSetStep(Edit<sd::SdfSetStep>),
    /// Move the fused result (a similarity; every fused operand moves and
    /// the grid is rebuilt).
    "sdf_move_fused" => SdfMoveFused(Edit<sd::SdfMoveFused>),
    /// Copy the fused result as a new user component, queued as an operand
    /// where the result is (moved by a transform).
    "sdf_copy_fused" => SdfCopyFused(Edit<sd::SdfCopyFused>),
    /// Make a user component from any closed object of the document,
    /// optionally queued where the object is.
    "sdf_component_from_object" => SdfComponentFromObject(Edit<sd::SdfComponentFromObject>),
    /// Create an empty curve network (styling).
    "curve_network_create" => CurveNetworkCreate(Create<st::CurveNetworkCreate>),
    /// Draw a curve into a network from tracked samples.
    "curve_draw" => CurveDraw(Edit<st::CurveDraw>),
    /// Draw a curve in the modeling frame held by the other hand; the
    /// network moves with the frame.
    "curve_draw_in_frame" => CurveDrawInFrame(st::CurveDrawInFrame),
    /// Curve smoother held along a pointer path.
    "curve_smooth" => CurveSmooth(Edit<st::CurveSmooth>),
    /// Curve sharpener held along a pointer path.
    "curve_sharpen" => CurveSharpen(Edit<st::CurveSharpen>),
    /// Curve puller held along a pointer path.
    "curve_pull" => CurvePull(Edit<st::CurvePull>),
    /// Curve attractor (point, line, plane or another curve) held for a
    /// number of frames.
    "curve_attract" => CurveAttract(Edit<st::CurveAttract>),
    /// Delete a network curve (and the patches using it).
    "curve_delete" => CurveDelete(Edit<st::CurveDelete>),
    /// Fill an explicitly picked loop with a patch.
    "curve_fill_loop" => CurveFillLoop(Edit<st::CurveFillLoop>),
    /// Fill every automatically found loop.
    "curve_fill_auto" => CurveFillAuto(Edit<st::CurveFillAuto>),
    /// Surface smoother on a patch.
    "surface_smooth" => SurfaceSmooth(Edit<st::SurfaceSmooth>),
    /// Surface sharpener on a patch.
    "surface_sharpen" => SurfaceSharpen(Edit<st::SurfaceSharpen>),
    /// Surface puller on a patch.
    "surface_pull" => SurfacePull(Edit<st::SurfacePull>),
    /// Add a child GC starting on a part's surface.
    "gc_add_child" => GcAddChild(Edit<asm::GcAddChild>),
    /// Copy a part with its descendants (optionally mirrored).
    "gc_copy" => GcCopy(Edit<asm::GcCopy>),
    /// Move a part rigidly; twins mirror it, children follow.
    "gc_transform_part" => GcTransformPart(Edit<asm::GcTransformPart>),
    /// Edit a part with structure-aware propagation.
    "gc_edit_part" => GcEditPart(Edit<asm::GcEditPart>),
    /// Release a recorded relation (coplanar, concentric, symmetric) so
    /// later edits may break it.
    "gc_release" => GcRelease(Edit<asm::GcRelease>),
    /// Give an object a name (hosts show it; it does not change geometry).
    "rename_object" => RenameObject(RenameObject),
    /// Set the document's wall thickness for printing surfaces as solids.
    "set_wall_thickness" => SetWallThickness(pr::SetWallThickness),
    /// Choose whether an edit that folds its object through itself is
    /// refused or applied and flagged as not printable.
    "set_self_intersection_policy" => SetSelfIntersectionPolicy(pr::SetSelfIntersectionPolicy),
    /// Set the printer the document is for (its build volume): a preset
    /// or a custom size; exports say when the model does not fit it.
    "set_printer" => SetPrinter(pr::SetPrinter),
    /// Take the next created objects' ids from a given one on (written by
    /// shared sessions, so ids made by different people never collide).
    "reserve_ids" => ReserveIds(ReserveIds),
}
