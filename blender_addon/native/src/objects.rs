//! What a host asks of each object on every sync, answered without
//! touching its mesh when the object did not change: its origin
//! (`Object::origin`), the key of its mesh in that frame (equal keys:
//! the host's copy of the mesh is still right) and its content hash.
//!
//! An object that changed has a new mesh (`Object::mesh` is a fresh
//! `Arc` whenever it is re-evaluated or placed); the cache holds the old
//! `Arc`, so its address cannot be reused while it is compared. A big
//! document's sync then costs one pointer comparison per unchanged
//! object, not a hash of millions of triangles (the add-on used to hash
//! every object's mesh after every op).

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use shapewright::doc::{ContentHasher, Document, Object, ObjectId};
use shapewright::math::Transform;
use shapewright::mesh::TriMesh;

use crate::error::op_err;
use pyo3::PyResult;

/// One object as last seen.
#[derive(Clone, Debug)]
struct Known {
    mesh: Arc<TriMesh>,
    local: Arc<TriMesh>,
    origin: Transform,
    shape: u64,
    /// The object's name and content hash, once asked for.
    hash: Option<(String, u64)>,
}

/// The cache, by object id.
#[derive(Debug, Default)]
pub(crate) struct Objects(Mutex<HashMap<u32, Known>>);

fn shape_hash(obj: &Object) -> PyResult<u64> {
    let m = obj.origin_mesh().map_err(op_err)?;
    let mut h = ContentHasher::new();
    h.mesh(&m);
    Ok(h.finish())
}

impl Objects {
    fn with<R>(
        &self,
        doc: &Document,
        id: u32,
        f: impl FnOnce(&Object, &mut Known) -> R,
    ) -> PyResult<R> {
        let obj = doc.get(ObjectId(id)).map_err(op_err)?;
        let mut map = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let known = match map.get_mut(&id) {
            Some(k) if Arc::ptr_eq(&k.mesh, &obj.mesh) => k,
            other => {
                // Kinds placed by the object keep their own-frame mesh when
                // moved: the shape key stays.
                let shape = match other {
                    Some(k)
                        if obj.kind.own_transform().is_none()
                            && Arc::ptr_eq(&k.local, &obj.local_mesh) =>
                    {
                        k.shape
                    }
                    _ => shape_hash(obj)?,
                };
                map.insert(
                    id,
                    Known {
                        mesh: obj.mesh.clone(),
                        local: obj.local_mesh.clone(),
                        origin: obj.origin(),
                        shape,
                        hash: None,
                    },
                );
                map.get_mut(&id).expect("just inserted")
            }
        };
        Ok(f(obj, known))
    }

    /// The object's origin.
    pub(crate) fn origin(&self, doc: &Document, id: u32) -> PyResult<Transform> {
        self.with(doc, id, |_, k| k.origin)
    }

    /// The key of the object's mesh in its origin's frame.
    pub(crate) fn shape_key(&self, doc: &Document, id: u32) -> PyResult<String> {
        self.with(doc, id, |_, k| format!("{:016x}", k.shape))
    }

    /// `Document::object_hash`, computed once per version of the object
    /// (and again after a rename, which changes the name alone).
    pub(crate) fn hash(&self, doc: &Document, id: u32) -> PyResult<u64> {
        let cached = self.with(doc, id, |obj, k| {
            k.hash
                .as_ref()
                .filter(|(name, _)| *name == obj.name)
                .map(|(_, h)| *h)
        })?;
        if let Some(h) = cached {
            return Ok(h);
        }
        let full = doc.object_hash(ObjectId(id)).map_err(op_err)?;
        self.with(doc, id, |obj, k| {
            k.hash = Some((obj.name.clone(), full));
            full
        })
    }
}
