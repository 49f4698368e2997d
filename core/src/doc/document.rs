//! [`Document`]: objects by id.

use std::collections::BTreeMap;
use std::sync::Arc;

use super::{ContentHasher, Object, ObjectId, ObjectKind, OpError};
use crate::mesh::{union, BooleanError, TriMesh};

/// Objects by stable id, plus the id counter. Cloning is cheap: objects
/// are shared until one is changed.
#[derive(Clone, Debug, Default)]
pub struct Document {
    objects: BTreeMap<ObjectId, Arc<Object>>,
    next_id: u32,
    work: u64,
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
        ObjectId(self.next_id + 1)
    }

    /// Evaluates `kind` and inserts it under a newly allocated id.
    pub fn insert(&mut self, kind: ObjectKind) -> Result<ObjectId, OpError> {
        let id = self.next_id();
        let obj = self.build(id, kind)?;
        self.next_id = id.0;
        self.objects.insert(id, Arc::new(obj));
        Ok(id)
    }

    /// Replaces the object `id` with `kind`, re-evaluating its mesh.
    pub fn replace(&mut self, id: ObjectId, kind: ObjectKind) -> Result<(), OpError> {
        self.get(id)?;
        let obj = self.build(id, kind)?;
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

    fn build(&mut self, id: ObjectId, kind: ObjectKind) -> Result<Object, OpError> {
        let mut mesh = kind.evaluate()?;
        self.work += mesh.triangles.len() as u64 + 1;
        mesh.set_source(id.0);
        Ok(Object {
            kind,
            mesh: Arc::new(mesh),
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
        for (id, obj) in &self.objects {
            h.u64(id.0 as u64);
            // Parameters: serde_json prints f64 exactly (shortest round-trip).
            h.bytes(
                serde_json::to_string(&obj.kind)
                    .unwrap_or_default()
                    .as_bytes(),
            );
            h.mesh(&obj.mesh);
        }
        h.finish()
    }
}
