//! Where a stage keeps a Shapewright document: the log prim and the
//! object prims.
//!
//! Files Shapewright writes have `/ShapewrightLog` and `/World/Object_<id>`
//! (see the crate doc). Other hosts move things: Blender's USD exporter,
//! with the add-on's export hook, puts everything under its root prim
//! (`/root` by default, any path the user sets) and names object prims
//! after the Blender objects. So the log is the first prim named
//! `ShapewrightLog` found breadth-first, and the objects are the prims
//! carrying `shapewright:objectId`, wherever they are; an object's mesh is
//! its child `Mesh`, or else its first child of type `Mesh`.

use std::collections::{BTreeMap, VecDeque};

use openusd::sdf::{self, AbstractData, Value};
use shapewright::doc::ObjectId;

use crate::kinds::MESH_PRIM;
use crate::load::{as_int, attr_value, children, field};
use crate::{LOG_PRIM, WORLD_PRIM};

/// Most prims visited while looking for the log or the objects (a guard
/// against pathological stages; real scenes have far fewer).
pub const MAX_PRIMS_SEARCHED: usize = 1_000_000;

/// The object prims of a stage.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjectPrims {
    /// Each object's prim.
    pub objects: BTreeMap<ObjectId, sdf::Path>,
    /// Object prims without a usable (or with a repeated) id.
    pub extra: Vec<String>,
}

/// The path of the log prim: `/ShapewrightLog`, or the first prim of that
/// name breadth-first (e.g. `/root/ShapewrightLog` in a Blender export).
pub fn find_log(data: &dyn AbstractData) -> Option<sdf::Path> {
    let root = sdf::Path::abs_root();
    let direct = root.append_path(LOG_PRIM).ok()?;
    if data.has_spec(&direct) {
        return Some(direct);
    }
    let mut found = None;
    breadth_first(data, |c, name| {
        if name == LOG_PRIM {
            found = Some(c.clone());
            Visit::Stop
        } else {
            Visit::Descend
        }
    });
    found
}

/// What a breadth-first search does with a prim it reaches.
enum Visit {
    /// Ends the search.
    Stop,
    /// Searches the prim's children too.
    Descend,
    /// Goes on without its children.
    Skip,
}

/// Visits the prims below the root breadth-first, at most
/// [`MAX_PRIMS_SEARCHED`] of them (a hostile file is not searched to its
/// end): `visit(prim, name)` says how to go on.
fn breadth_first(data: &dyn AbstractData, mut visit: impl FnMut(&sdf::Path, &str) -> Visit) {
    let mut queue: VecDeque<sdf::Path> = VecDeque::from([sdf::Path::abs_root()]);
    let mut seen = 0usize;
    while let Some(p) = queue.pop_front() {
        for name in children(data, &p) {
            seen += 1;
            if seen > MAX_PRIMS_SEARCHED {
                return;
            }
            let Ok(c) = p.append_path(name.as_str()) else {
                continue;
            };
            match visit(&c, name.as_str()) {
                Visit::Stop => return,
                Visit::Descend => queue.push_back(c),
                Visit::Skip => {}
            }
        }
    }
}

fn object_id(data: &dyn AbstractData, prim: &sdf::Path) -> Option<Option<ObjectId>> {
    let v = attr_value(data, prim, "shapewright:objectId")?;
    Some(as_int(&v).and_then(|i| u32::try_from(i).ok()).map(ObjectId))
}

/// The object prims: the children of `/World` in Shapewright's own files;
/// else every prim carrying `shapewright:objectId` (its subtree is not
/// searched further).
pub fn object_prims(data: &dyn AbstractData) -> ObjectPrims {
    let mut out = ObjectPrims::default();
    let root = sdf::Path::abs_root();
    let add = |out: &mut ObjectPrims, path: sdf::Path, id: Option<ObjectId>| match id {
        Some(id) if !out.objects.contains_key(&id) => {
            out.objects.insert(id, path);
        }
        _ => out.extra.push(path.as_str().to_owned()),
    };
    if let Ok(world) = root.append_path(WORLD_PRIM) {
        if data.has_spec(&world) {
            for name in children(data, &world) {
                if let Ok(obj) = world.append_path(name.as_str()) {
                    let id = object_id(data, &obj).flatten();
                    add(&mut out, obj, id);
                }
            }
            return out;
        }
    }
    breadth_first(data, |c, _| match object_id(data, c) {
        Some(id) => {
            add(&mut out, c.clone(), id);
            Visit::Skip
        }
        None => Visit::Descend,
    });
    out
}

/// The mesh prim of an object prim: its child `Mesh`, else its first child
/// whose type is `Mesh` (Blender names it after the mesh data).
pub fn mesh_of(data: &dyn AbstractData, object: &sdf::Path) -> Option<sdf::Path> {
    let named = object.append_path(MESH_PRIM).ok()?;
    if data.has_spec(&named) {
        return Some(named);
    }
    children(data, object).into_iter().find_map(|name| {
        let c = object.append_path(name.as_str()).ok()?;
        let t = field(data, &c, "typeName")?;
        matches!(t.as_ref(), Value::Token(t) if t.as_str() == "Mesh").then_some(c)
    })
}
