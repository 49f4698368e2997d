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
use serde::de::{DeserializeOwned, Error as _};
use serde::ser::{Error as _, SerializeMap};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::{Document, KindOf, ObjectId, OpError};
use crate::mesh::TriMesh;

mod gc;
pub mod object;
mod print;
mod sculpt;
mod sdf;
pub mod solid;
mod styling;

pub use object::{Delete, Duplicate, RenameObject, ReserveIds, SetTransform, TransformBy};
pub use solid::{AddSolid, EditSolid};

/// What applying an op produced.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OpOutcome {
    /// The id of the object the op created, if it created one.
    pub created: Option<ObjectId>,
}

/// What an op's apply may read besides the object it edits: the document
/// before the op (other objects' meshes, for brushes and bases made from
/// them), and a place to record work that meshing does not show.
pub struct EditCx<'a> {
    doc: &'a Document,
    /// The object edited (`None` for creations).
    target: Option<ObjectId>,
    work: u64,
}

impl EditCx<'_> {
    /// The current mesh of object `id` (model space), as the document has it
    /// before this op.
    pub fn mesh(&self, id: ObjectId) -> Result<&TriMesh, OpError> {
        Ok(&self.doc.get(id)?.mesh)
    }

    /// The placement of the object being edited (its own frame to model
    /// space; identity for creations).
    pub fn target_placement(&self) -> Result<crate::math::Transform, OpError> {
        match self.target {
            Some(id) => Ok(self.doc.get(id)?.transform()),
            None => Ok(crate::math::Transform::IDENTITY),
        }
    }

    /// Records `amount` units of work beyond meshing (see
    /// [`Document::add_work`]), so checkpoints stay spaced by work done.
    pub fn add_work(&mut self, amount: u64) {
        self.work += amount;
    }
}

/// An edit of one object of kind [`ObjectEdit::Target`].
pub trait ObjectEdit {
    /// The kind of object edited.
    type Target: KindOf;
    /// The JSON field that names the object (`id`; SDF ops say `volume`).
    const ID_FIELD: &'static str = "id";
    /// True for edits that can fold an object through itself (GC and
    /// sculpt edits): after the edit, the object's mesh is checked under
    /// the document's self-intersection policy ([`crate::print::check_edit`]).
    const CHECK_FOLDS: bool = false;
    /// Edits `target` (a copy of the object's kind; stored only on success).
    fn apply(&self, target: &mut Self::Target, cx: &mut EditCx<'_>) -> Result<(), OpError>;
}

/// The creation of one new object.
pub trait ObjectCreate {
    /// The kind created.
    type Target: KindOf;
    /// True for creations that can make an object passing through itself
    /// (see [`ObjectEdit::CHECK_FOLDS`]).
    const CHECK_FOLDS: bool = false;
    /// Builds the new object's kind.
    fn build(&self, cx: &mut EditCx<'_>) -> Result<Self::Target, OpError>;
}

/// How a payload applies to the document (implemented by [`Edit`],
/// [`Create`] and the document ops).
pub trait Apply {
    /// The object kind the op acts on (`"solid"`, `"gc_assembly"`, ...), or
    /// `"document"` for ops on any object.
    const KIND: &'static str;
    /// Applies the op. On error `doc` may be partly changed: call through
    /// [`super::OpLog::apply`], which applies to a copy.
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError>;
}

/// An edit `edit` of the object `id`. On the wire the id is one more field
/// of the edit's JSON object (named [`ObjectEdit::ID_FIELD`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Edit<T> {
    /// The object edited.
    pub id: ObjectId,
    /// What is done to it.
    pub edit: T,
}

impl<T> Edit<T> {
    /// `edit` of object `id`.
    pub fn new(id: ObjectId, edit: T) -> Self {
        Self { id, edit }
    }
}

/// An edit reads as its payload (`op.section`, `op.samples`); the id is
/// `op.id`.
impl<T> std::ops::Deref for Edit<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.edit
    }
}

impl<T> std::ops::DerefMut for Edit<T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.edit
    }
}

impl<T: ObjectEdit> Apply for Edit<T> {
    const KIND: &'static str = <T::Target as KindOf>::NAME;
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        let mut target = doc.get_as::<T::Target>(self.id)?.clone();
        let mut cx = EditCx {
            doc,
            target: Some(self.id),
            work: 0,
        };
        self.edit.apply(&mut target, &mut cx)?;
        let work = cx.work;
        doc.add_work(work);
        let before = T::CHECK_FOLDS.then(|| doc.get(self.id).map(|o| o.mesh.clone()));
        doc.replace(self.id, target.into_kind())?;
        if let Some(before) = before {
            print::check_fold(doc, self.id, Some(&before?))?;
        }
        Ok(OpOutcome::default())
    }
}

impl<T: ObjectEdit + Serialize> Serialize for Edit<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let serde_json::Value::Object(fields) =
            serde_json::to_value(&self.edit).map_err(S::Error::custom)?
        else {
            return Err(S::Error::custom("an edit must serialize as a JSON object"));
        };
        let mut map = s.serialize_map(Some(fields.len() + 1))?;
        map.serialize_entry(T::ID_FIELD, &self.id)?;
        for (k, v) in &fields {
            map.serialize_entry(k, v)?;
        }
        map.end()
    }
}

impl<'de, T: ObjectEdit + DeserializeOwned> Deserialize<'de> for Edit<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let mut fields = serde_json::Map::<String, serde_json::Value>::deserialize(d)?;
        let id = fields
            .shift_remove(T::ID_FIELD)
            .ok_or_else(|| D::Error::missing_field(T::ID_FIELD))?;
        let id = ObjectId::deserialize(id)
            .map_err(|e| D::Error::custom(format!("field `{}`: {e}", T::ID_FIELD)))?;
        let edit = T::deserialize(serde_json::Value::Object(fields)).map_err(D::Error::custom)?;
        Ok(Self { id, edit })
    }
}

impl<T: ObjectEdit + JsonSchema> JsonSchema for Edit<T> {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        T::schema_name()
    }

    fn schema_id() -> std::borrow::Cow<'static, str> {
        T::schema_id()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        let mut schema = T::json_schema(generator);
        // A transparent payload (a newtype) comes back as a reference to
        // its inner type: inline it, so the id joins its properties.
        for _ in 0..4 {
            let Some(name) = schema
                .get("$ref")
                .and_then(|r| r.as_str())
                .and_then(|r| r.rsplit('/').next())
                .map(str::to_owned)
            else {
                break;
            };
            let Some(def) = generator.definitions().get(&name).cloned() else {
                break;
            };
            let mut inlined: schemars::Schema = serde_json::from_value(def).unwrap_or_default();
            if let (Some(o), Some(d)) = (inlined.as_object_mut(), schema.get("description")) {
                o.entry("description").or_insert_with(|| d.clone());
            }
            schema = inlined;
        }
        let id_schema = generator.subschema_for::<ObjectId>();
        let mut id_schema = serde_json::to_value(id_schema).unwrap_or_default();
        if let Some(o) = id_schema.as_object_mut() {
            o.insert(
                "description".into(),
                format!(
                    "The {} object this op edits.",
                    <T::Target as KindOf>::NAME.replace('_', " ")
                )
                .into(),
            );
        }
        if let Some(obj) = schema.as_object_mut() {
            let props = obj
                .entry("properties")
                .or_insert_with(|| serde_json::Value::Object(Default::default()));
            if let Some(props) = props.as_object_mut() {
                let mut with_id = serde_json::Map::new();
                with_id.insert(T::ID_FIELD.into(), id_schema);
                with_id.extend(std::mem::take(props));
                *props = with_id;
            }
            let req = obj
                .entry("required")
                .or_insert_with(|| serde_json::Value::Array(Vec::new()));
            if let Some(req) = req.as_array_mut() {
                req.insert(0, T::ID_FIELD.into());
            }
        }
        schema
    }
}

/// The creation of an object by `T`. On the wire, `T`'s own fields.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Create<T>(pub T);

impl<T: JsonSchema> JsonSchema for Create<T> {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        T::schema_name()
    }
    fn schema_id() -> std::borrow::Cow<'static, str> {
        T::schema_id()
    }
    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        T::json_schema(generator)
    }
    fn inline_schema() -> bool {
        true
    }
}

impl<T: ObjectCreate> Apply for Create<T> {
    const KIND: &'static str = <T::Target as KindOf>::NAME;
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        let mut cx = EditCx {
            doc,
            target: None,
            work: 0,
        };
        let kind = self.0.build(&mut cx)?;
        let work = cx.work;
        doc.add_work(work);
        let id = doc.insert(kind.into_kind())?;
        if T::CHECK_FOLDS {
            print::check_fold(doc, id, None)?;
        }
        Ok(OpOutcome { created: Some(id) })
    }
}

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
