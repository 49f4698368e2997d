//! Each participant's id range ([`id_range`]) and applying an op inside
//! it, shared by the replica and the client so both decide identically.

use crate::doc::Op;

/// How many people can join one document (each gets an id range).
pub const MAX_PARTICIPANTS: u32 = 127;

/// Ids of participant `slot` are `slot << ID_RANGE_BITS` and up.
pub const ID_RANGE_BITS: u32 = 24;

/// The first and one past the last id of participant `slot`'s range.
pub fn id_range(slot: u32) -> (u32, u32) {
    let first = (slot << ID_RANGE_BITS) + 1;
    (first, (slot + 1) << ID_RANGE_BITS)
}

/// Applies `op` to `doc` taking ids from `ids_from` (if any); every id it
/// takes must lie in `range` (its author's). A reservation that created
/// nothing is taken back, so the document is as if it was never made.
/// Shared by the replica and the client so both decide identically.
pub(super) fn apply_op(
    doc: &mut crate::doc::Document,
    op: &Op,
    ids_from: Option<u32>,
    range: (u32, u32),
) -> Result<crate::doc::OpOutcome, crate::doc::OpError> {
    use crate::doc::{ObjectId, OpError};
    crate::doc::schema::check_op(op)?;
    let saved = doc.id_block();
    let last = doc.last_id();
    if let Some(first) = ids_from {
        if first < range.0 || first >= range.1 {
            return Err(OpError::IdOutsideRange(ObjectId(first)));
        }
        doc.reserve_ids(first)?;
    }
    let outcome = op.apply(doc)?;
    match ids_from {
        Some(first) => {
            let end = doc.id_block().unwrap_or(first);
            if end == first {
                doc.set_id_block(saved);
            } else if end > range.1 {
                return Err(OpError::IdOutsideRange(ObjectId(end - 1)));
            }
        }
        None if doc.last_id() != last || doc.id_block() != saved => {
            return Err(OpError::IdOutsideRange(doc.next_id()));
        }
        None => {}
    }
    Ok(outcome)
}
