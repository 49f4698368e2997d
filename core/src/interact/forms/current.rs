//! What an edit's form starts from: the object's current values, so a
//! form applied without typing anything changes nothing ("Mesh
//! Resolution" used to drop a GC from 12,480 triangles to 40; "Set
//! Placement" sent an object to the origin).

use serde_json::{json, Map, Value};

use crate::doc::{Document, ObjectId, ObjectKind};
use crate::gc::{Gc, ShapeType};

fn part(doc: &Document, id: ObjectId, part: usize) -> Option<&Gc> {
    match &doc.get(id).ok()?.kind {
        ObjectKind::GcAssembly(a) => a.parts.get(part).map(|p| &p.gc),
        _ => None,
    }
}

/// The current values of op `op`'s fields on object `id` (part `part` of
/// an assembly): by form field name for an op with a form (`shape_type`,
/// `thickness`), else the op's own fields as the op holds them
/// (`{"transform": {"translate", "rotate", "scale"}}`); lengths in
/// metres, rotations as quaternions. Empty when the op does not start
/// from current values or the object has none (a missing part, another
/// kind): the form's defaults stand.
pub fn current(op: &str, doc: &Document, id: ObjectId, part_index: usize) -> Map<String, Value> {
    let to = |v: Value| match v {
        Value::Object(m) => m,
        _ => Map::new(),
    };
    match op {
        "set_transform" => match doc.get(id) {
            Ok(obj) => to(json!({ "transform": ser(&obj.transform()) })),
            Err(_) => Map::new(),
        },
        "gc_set_resolution" => part(doc, id, part_index)
            .map(|g| to(json!({ "resolution": ser(&g.resolution) })))
            .unwrap_or_default(),
        "gc_set_shape" => part(doc, id, part_index)
            .map(|g| shape_values(&g.shape))
            .unwrap_or_default(),
        "edit_solid" => match doc.get(id).map(|o| &o.kind) {
            Ok(ObjectKind::Solid(s)) => to(json!({
                "shape": s.shape.name(),
                "dimensions": s.shape.dimensions(),
                "segments": s.segments,
            })),
            _ => Map::new(),
        },
        "sdf_set_step" => match doc.get(id).map(|o| &o.kind) {
            Ok(ObjectKind::SdfVolume(v)) => to(json!({ "step": v.step })),
            _ => Map::new(),
        },
        _ => Map::new(),
    }
}

fn ser(x: &impl serde::Serialize) -> Value {
    serde_json::to_value(x).unwrap_or_default()
}

/// A GC's shape type as the shape fields of a form (the inverse of the
/// form's `shape_type`, `thickness`, `closed_end`).
fn shape_values(shape: &ShapeType) -> Map<String, Value> {
    let mut out = Map::new();
    let Value::Object(m) = serde_json::to_value(shape).unwrap_or_default() else {
        return out;
    };
    for (k, v) in m {
        out.insert(if k == "type" { "shape_type".into() } else { k }, v);
    }
    out
}
