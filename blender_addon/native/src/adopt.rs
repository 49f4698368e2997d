//! Blender's own edits of Shapewright objects (G/R/S, F2, Shift-D, X)
//! become ops here, so the add-on spells out no op: it says what Blender
//! did, and this picks the op.
//!
//! Each edit is *redone* instead of recorded when the next op of the
//! redo tail is that very edit. Blender pushes its undo step for an edit
//! before the add-on records the op, so that step holds the edit with
//! the log before it; when Blender's undo or redo comes back to that
//! step, the log's next op is redone (keeping the rest of the tail) and
//! the document and Blender agree again.

use pyo3::prelude::*;
use shapewright::doc::{Delete, Duplicate, ObjectId, Op, RenameObject, SetTransform};

use crate::doc::Session;
use crate::error::op_err;
use crate::placement::Placement;

/// Redoes `op` when it is the next op, else applies it. Returns
/// `redone` or `applied`, and the id the op created.
fn take(s: &mut Session, py: Python<'_>, op: Op) -> PyResult<(&'static str, Option<u32>)> {
    if s.next() == Some(&op) {
        let before = s.log.document().next_id();
        let log = &mut s.log;
        py.detach(|| log.redo()).map_err(crate::error::log_err)?;
        let created = (s.log.document().next_id() != before).then_some(before.0);
        return Ok(("redone", created));
    }
    let created = s.apply_op(py, op)?;
    Ok(("applied", created))
}

/// See `Session.adopt_placement`.
pub(crate) fn placement(
    s: &mut Session,
    py: Python<'_>,
    id: u32,
    origin: &Placement,
) -> PyResult<&'static str> {
    let now = s.objects.origin(s.log.document(), id)?;
    if Placement(now).close_to(origin, 0.0) {
        return Ok("same");
    }
    let obj = s.log.document().get(ObjectId(id)).map_err(op_err)?;
    let transform = obj.placement_for_origin(&origin.0).map_err(op_err)?;
    let op = Op::SetTransform(SetTransform {
        id: ObjectId(id),
        transform,
    });
    take(s, py, op).map(|(how, _)| how)
}

/// See `Session.adopt_name`.
pub(crate) fn name(s: &mut Session, py: Python<'_>, id: u32, name: &str) -> PyResult<&'static str> {
    let obj = s.log.document().get(ObjectId(id)).map_err(op_err)?;
    if obj.name == name {
        return Ok("same");
    }
    let op = Op::RenameObject(RenameObject {
        id: ObjectId(id),
        name: name.to_string(),
    });
    take(s, py, op).map(|(how, _)| how)
}

/// See `Session.adopt_duplicate`.
pub(crate) fn duplicate(s: &mut Session, py: Python<'_>, id: u32) -> PyResult<(&'static str, u32)> {
    let op = Op::Duplicate(Duplicate { id: ObjectId(id) });
    let (how, created) = take(s, py, op)?;
    let created = created.ok_or_else(|| op_err(shapewright::doc::OpError::BadId(ObjectId(id))))?;
    Ok((how, created))
}

/// See `Session.adopt_delete`.
pub(crate) fn delete(s: &mut Session, py: Python<'_>, id: u32) -> PyResult<&'static str> {
    let op = Op::Delete(Delete { id: ObjectId(id) });
    take(s, py, op).map(|(how, _)| how)
}
