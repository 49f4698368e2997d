//! How an op applies: the three shapes of op ([`Edit<T>`] of one object
//! through its [`ObjectEdit`] impl, [`Create<T>`] through [`ObjectCreate`],
//! and any [`Apply`]), the context an edit gets ([`EditCx`]) and what
//! applying produced ([`OpOutcome`]). The op table itself is in `mod.rs`.

use schemars::JsonSchema;
use serde::de::{DeserializeOwned, Error as _};
use serde::ser::{Error as _, SerializeMap};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::print;
use crate::doc::{Document, KindOf, ObjectId, OpError};
use crate::mesh::TriMesh;

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
    pub(super) doc: &'a Document,
    /// The object edited (`None` for creations).
    pub(super) target: Option<ObjectId>,
    pub(super) work: u64,
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

    /// The document's print settings (wall thickness, printer) before
    /// this op.
    pub fn print_setup(&self) -> &crate::print::PrintSetup {
        self.doc.print_setup()
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
    /// [`crate::doc::OpLog::apply`], which applies to a copy.
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
