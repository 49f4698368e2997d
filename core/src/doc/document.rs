//! [`Document`]: objects by id.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::{ContentHasher, KindOf, Object, ObjectId, ObjectKind, OpError};
use crate::math::Transform;
use crate::mesh::{union, BooleanError, TriMesh};
use crate::print::PrintSetup;

/// Objects by stable id, plus the id counter. Cloning is cheap: objects
/// are shared until one is changed.
///
/// Serialized as `{"last_id": N, "objects": [{"id": 1, "kind": {...}}, ...]}`
/// (plus `"print": {...}` when the print setup is not the default):
/// kinds only, never meshes. Deserializing re-evaluates every mesh (ops are
/// deterministic, so the meshes come back bit-identical) and refuses ids that
/// are zero, repeated, out of order or above `last_id`.
#[derive(Clone, Debug, Default)]
pub struct Document {
    objects: BTreeMap<ObjectId, Arc<Object>>,
    next_id: u32,
    work: u64,
    print: PrintSetup,
    /// The id the next created object gets, once a shared session has
    /// placed it (`reserve_ids`): each participant creates objects in its
    /// own id range, so objects made at the same time by two people never
    /// collide and keep their ids when one person's ops are rebased onto
    /// the other's. `None` (every single-user document): ids follow
    /// `next_id`, as they always did.
    block: Option<u32>,
}

impl Document {
    /// An empty document.
    pub fn new() -> Self {
        Self::default()
    }

    /// The object with id `id`.
    pub fn get(&self, id: ObjectId) -> Result<&Object, OpError> {
        self.objects
            .get(&id)
            .map(|o| o.as_ref())
            .ok_or(OpError::BadId(id))
    }

    /// The object `id` as kind `K`, or [`OpError::WrongKind`] (the op name
    /// is filled in by [`super::Op::apply`]).
    pub fn get_as<K: KindOf>(&self, id: ObjectId) -> Result<&K, OpError> {
        let obj = self.get(id)?;
        K::of(&obj.kind).ok_or(OpError::WrongKind {
            id,
            op: "",
            expected: K::NAME,
            found: obj.kind.name(),
        })
    }

    /// Objects in id order.
    pub fn objects(&self) -> impl Iterator<Item = (ObjectId, &Object)> {
        self.objects.iter().map(|(id, o)| (*id, o.as_ref()))
    }

    /// Number of objects.
    pub fn len(&self) -> usize {
        self.objects.len()
    }

    /// True when the document has no objects.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// The id the next created object will get.
    pub fn next_id(&self) -> ObjectId {
        ObjectId(self.block.unwrap_or(self.next_id.saturating_add(1)))
    }

    /// The id block a shared session placed (`None`: ids follow
    /// [`Self::last_id`]).
    pub fn id_block(&self) -> Option<u32> {
        self.block
    }

    /// Restores the id block (a shared session undoing a reservation that
    /// created nothing, see `doc::shared`).
    pub(super) fn set_id_block(&mut self, block: Option<u32>) {
        self.block = block;
    }

    /// The highest id ever given to an object (0: none yet).
    pub fn last_id(&self) -> u32 {
        self.next_id
    }

    /// Makes the next created objects take ids `first`, `first + 1`, ...
    /// (`reserve_ids`; a shared session places each person's creations in
    /// their own range). An id already in use is refused when an object
    /// would take it ([`OpError::IdInUse`]), never overwritten.
    pub fn reserve_ids(&mut self, first: u32) -> Result<(), OpError> {
        if first == 0 || first == u32::MAX {
            return Err(OpError::BadIdBlock(first));
        }
        self.block = Some(first);
        Ok(())
    }

    /// The id a new object gets, checked to be free (inserted by
    /// [`Self::take_id`] once the object is built).
    fn fresh_id(&self) -> Result<ObjectId, OpError> {
        let id = self.next_id();
        if id.0 == u32::MAX || self.objects.contains_key(&id) {
            return Err(OpError::IdInUse(id));
        }
        Ok(id)
    }

    fn take_id(&mut self, id: ObjectId) {
        self.next_id = self.next_id.max(id.0);
        if self.block.is_some() {
            self.block = Some(id.0 + 1);
        }
    }

    /// Evaluates `kind` and inserts it under a newly allocated id.
    pub fn insert(&mut self, kind: ObjectKind) -> Result<ObjectId, OpError> {
        let id = self.fresh_id()?;
        let obj = self.build(
            id,
            kind,
            String::new(),
            Transform::IDENTITY,
            Default::default(),
        )?;
        self.take_id(id);
        self.objects.insert(id, Arc::new(obj));
        Ok(id)
    }

    /// Replaces the object `id`'s kind with `kind` (keeping its name and
    /// placement), re-evaluating its mesh.
    pub fn replace(&mut self, id: ObjectId, kind: ObjectKind) -> Result<(), OpError> {
        let old = self.get(id)?;
        let (name, placement, cache) = (old.name.clone(), old.placement, old.cache.clone());
        let obj = self.build(id, kind, name, placement, cache)?;
        self.objects.insert(id, Arc::new(obj));
        Ok(())
    }

    /// Places object `id` at `t`: its own transform for kinds that have one
    /// (re-evaluated), else its object-level placement (the kind's mesh is
    /// moved once from its own frame, never re-evaluated or re-moved, so
    /// moves do not accumulate rounding).
    pub fn set_placement(&mut self, id: ObjectId, t: Transform) -> Result<(), OpError> {
        t.validate()?;
        let old = self.get(id)?.clone();
        let mut kind = old.kind.clone();
        let obj = if kind.set_own_transform(t)? {
            self.build(id, kind, old.name, Transform::IDENTITY, old.cache)?
        } else {
            let mesh = place(&old.local_mesh, &t)?;
            self.work += mesh.triangles.len() as u64 + 1;
            Object {
                placement: t,
                mesh,
                ..old
            }
        };
        self.objects.insert(id, Arc::new(obj));
        Ok(())
    }

    /// Copies object `id` (kind, name, placement and mesh) under a new id.
    pub fn duplicate(&mut self, id: ObjectId) -> Result<ObjectId, OpError> {
        let src = self.get(id)?.clone();
        let new = self.fresh_id()?;
        let mut local = (*src.local_mesh).clone();
        local.set_source(new.0);
        let local = Arc::new(local);
        let mesh = place(&local, &src.placement)?;
        self.work += mesh.triangles.len() as u64 + 1;
        self.take_id(new);
        self.objects.insert(
            new,
            Arc::new(Object {
                local_mesh: local,
                mesh,
                ..src
            }),
        );
        Ok(new)
    }

    /// Names object `id`.
    pub fn rename(&mut self, id: ObjectId, name: &str) -> Result<(), OpError> {
        let mut obj = self.get(id)?.clone();
        obj.name = name.to_string();
        self.objects.insert(id, Arc::new(obj));
        Ok(())
    }

    /// Removes the object `id`.
    pub fn remove(&mut self, id: ObjectId) -> Result<(), OpError> {
        self.objects
            .remove(&id)
            .map(|_| ())
            .ok_or(OpError::BadId(id))
    }

    /// The document's print settings (wall thickness, self-intersection
    /// policy).
    pub fn print_setup(&self) -> &PrintSetup {
        &self.print
    }

    /// Replaces the print settings (validated first).
    pub fn set_print_setup(&mut self, setup: PrintSetup) -> Result<(), OpError> {
        setup.validate()?;
        self.print = setup;
        Ok(())
    }

    /// Work done on this document so far: triangles meshed by evaluations.
    /// Not content (not hashed, not saved); the log uses it to place
    /// checkpoints deterministically.
    pub fn work(&self) -> u64 {
        self.work
    }

    /// Records `amount` units of work beyond meshing (for kinds whose ops
    /// do heavy work that their mesh size does not show).
    pub fn add_work(&mut self, amount: u64) {
        self.work += amount;
    }

    fn build(
        &mut self,
        id: ObjectId,
        kind: ObjectKind,
        name: String,
        placement: Transform,
        cache: crate::assembly::UnionCache,
    ) -> Result<Object, OpError> {
        let mut local = kind.evaluate_cached(&cache)?;
        self.work += local.triangles.len() as u64 + 1;
        local.set_source(id.0);
        let local_mesh = Arc::new(local);
        let mesh = place(&local_mesh, &placement)?;
        Ok(Object {
            kind,
            name,
            placement,
            local_mesh,
            mesh,
            cache,
        })
    }

    /// All objects' meshes appended into one buffer (not a boolean union;
    /// triangles keep their source ids).
    pub fn combined_mesh(&self) -> TriMesh {
        let mut out = TriMesh::default();
        for obj in self.objects.values() {
            out.append(&obj.mesh);
        }
        out
    }

    /// The printable model: the boolean union of every object's closed
    /// mesh, one closed oriented 2-manifold. Triangles keep the id of the
    /// object they came from.
    pub fn printable_mesh(&self) -> Result<TriMesh, BooleanError> {
        let meshes: Vec<&TriMesh> = self.objects.values().map(|o| o.mesh.as_ref()).collect();
        union(&meshes)
    }

    /// A hash of the document's content: ids, the id counter, every
    /// object's parameters and the bits of its evaluated mesh. Two documents
    /// with the same hash are, for every practical purpose, bit-identical.
    pub fn content_hash(&self) -> u64 {
        let mut h = ContentHasher::new();
        h.u64(self.next_id as u64);
        // Hashed only when set (shared sessions), so older documents keep
        // their hashes.
        if let Some(b) = self.block {
            h.bytes(b"id_block");
            h.u64(b as u64);
        }
        // Hashed only when changed, so older documents keep their hashes.
        if !self.print.is_default() {
            h.bytes(b"print");
            h.bytes(
                serde_json::to_string(&self.print)
                    .unwrap_or_default()
                    .as_bytes(),
            );
        }
        for (id, obj) in &self.objects {
            h.u64(id.0 as u64);
            hash_object(&mut h, obj);
        }
        h.finish()
    }

    /// A hash of one object's name, placement, parameters and mesh bits: it
    /// changes exactly when the object does (hosts re-sync only what
    /// changed).
    pub fn object_hash(&self, id: ObjectId) -> Result<u64, OpError> {
        let mut h = ContentHasher::new();
        hash_object(&mut h, self.get(id)?);
        Ok(h.finish())
    }
}

fn hash_object(h: &mut ContentHasher, obj: &Object) {
    // Names and object-level placements were added after the first
    // documents were recorded: hashed only when set, so those documents
    // keep their hashes.
    if !obj.name.is_empty() {
        h.bytes(b"name");
        h.bytes(obj.name.as_bytes());
    }
    if obj.placement != Transform::IDENTITY {
        h.bytes(b"placement");
        let t = &obj.placement;
        for x in t.translate.iter().chain(&t.rotate).chain(&t.scale) {
            h.f64(*x);
        }
    }
    // Parameters: serde_json prints f64 exactly (shortest round-trip).
    h.bytes(
        serde_json::to_string(&obj.kind)
            .unwrap_or_default()
            .as_bytes(),
    );
    h.mesh(&obj.mesh);
}

/// `local` placed by `t` (the same `Arc` when `t` is the identity).
fn place(local: &Arc<TriMesh>, t: &Transform) -> Result<Arc<TriMesh>, OpError> {
    if *t == Transform::IDENTITY {
        return Ok(local.clone());
    }
    let mut mesh = (**local).clone();
    mesh.transform(&t.to_affine()?);
    Ok(Arc::new(mesh))
}

#[derive(Serialize)]
struct DocumentOut<'a> {
    last_id: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    id_block: Option<u32>,
    #[serde(skip_serializing_if = "PrintSetup::is_default")]
    print: PrintSetup,
    objects: Vec<ObjectOut<'a>>,
}

#[derive(Serialize)]
struct ObjectOut<'a> {
    id: ObjectId,
    #[serde(skip_serializing_if = "str::is_empty")]
    name: &'a str,
    #[serde(skip_serializing_if = "is_identity")]
    placement: Transform,
    kind: &'a ObjectKind,
}

fn is_identity(t: &Transform) -> bool {
    *t == Transform::IDENTITY
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DocumentIn {
    last_id: u32,
    #[serde(default)]
    id_block: Option<u32>,
    #[serde(default)]
    print: PrintSetup,
    objects: Vec<ObjectIn>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectIn {
    id: ObjectId,
    #[serde(default)]
    name: String,
    #[serde(default)]
    placement: Transform,
    kind: ObjectKind,
}

impl Serialize for Document {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        DocumentOut {
            last_id: self.next_id,
            id_block: self.block,
            print: self.print,
            objects: self
                .objects
                .iter()
                .map(|(id, o)| ObjectOut {
                    id: *id,
                    name: &o.name,
                    placement: o.placement,
                    kind: &o.kind,
                })
                .collect(),
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for Document {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let input = DocumentIn::deserialize(d)?;
        input
            .print
            .validate()
            .map_err(|e| D::Error::custom(e.to_string()))?;
        let mut doc = Document {
            objects: BTreeMap::new(),
            next_id: input.last_id,
            work: 0,
            print: input.print,
            block: None,
        };
        if let Some(b) = input.id_block {
            doc.reserve_ids(b)
                .map_err(|e| D::Error::custom(e.to_string()))?;
        }
        let mut prev = 0;
        for o in input.objects {
            if o.id.0 <= prev || o.id.0 > input.last_id {
                return Err(D::Error::custom(format!(
                    "object id {} is zero, repeated, out of order or above last_id {}",
                    o.id, input.last_id
                )));
            }
            prev = o.id.0;
            let obj = doc
                .build(o.id, o.kind, o.name, o.placement, Default::default())
                .map_err(|e| D::Error::custom(format!("object {}: {e}", o.id)))?;
            doc.objects.insert(o.id, Arc::new(obj));
        }
        Ok(doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::doc::{Op, OpLog};

    #[test]
    fn serde_round_trip_is_bit_identical() {
        let mut log = OpLog::new();
        for line in [
            r#"{"op":"add_solid","shape":{"kind":"sphere","radius":0.5},"segments":24}"#,
            r#"{"op":"add_solid","shape":{"kind":"box","size":[1,2,3]}}"#,
            r#"{"op":"duplicate","id":1}"#,
            r#"{"op":"delete","id":2}"#,
        ] {
            log.apply(serde_json::from_str::<Op>(line).unwrap())
                .unwrap();
        }
        let doc = log.document();
        let text = serde_json::to_string(doc).unwrap();
        let back: Document = serde_json::from_str(&text).unwrap();
        assert_eq!(back.content_hash(), doc.content_hash());
        assert_eq!(back.next_id(), ObjectId(4));
        assert_eq!(back.len(), 2);
    }

    #[test]
    fn serde_refuses_bad_ids_and_bad_kinds() {
        let solid =
            r#"{"kind":"solid","shape":{"kind":"sphere","radius":1},"segments":16,"transform":{}}"#;
        for (ids, last) in [((0, 1), 3), ((2, 2), 3), ((2, 1), 3), ((1, 4), 3)] {
            let text = format!(
                r#"{{"last_id":{last},"objects":[{{"id":{},"kind":{solid}}},{{"id":{},"kind":{solid}}}]}}"#,
                ids.0, ids.1
            );
            assert!(serde_json::from_str::<Document>(&text).is_err(), "{text}");
        }
        let bad = r#"{"last_id":1,"objects":[{"id":1,"kind":{"kind":"solid","shape":{"kind":"sphere","radius":-1},"segments":16,"transform":{}}}]}"#;
        let err = serde_json::from_str::<Document>(bad)
            .unwrap_err()
            .to_string();
        assert!(err.contains("object #1"), "{err}");
    }
}
