//! The print ops (issues 17 and 31): `set_wall_thickness`,
//! `set_self_intersection_policy` and `set_printer` change the document's
//! [`crate::print::PrintSetup`]; [`check_fold`] is the edit-time check GC
//! and sculpt ops run after they apply (see [`super::ObjectEdit::CHECK_FOLDS`]).

use std::sync::Arc;

use super::{Apply, OpOutcome};
use crate::doc::{Document, ObjectId, OpError};
use crate::mesh::TriMesh;
use crate::print::{
    check_edit, PrintSetup, Printer, SelfIntersectionPolicy, SetPrinter, SetSelfIntersectionPolicy,
    SetWallThickness,
};

impl Apply for SetWallThickness {
    const KIND: &'static str = "document";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        doc.set_print_setup(PrintSetup {
            wall_thickness: self.thickness,
            ..*doc.print_setup()
        })?;
        Ok(OpOutcome::default())
    }
}

impl Apply for SetSelfIntersectionPolicy {
    const KIND: &'static str = "document";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        doc.set_print_setup(PrintSetup {
            on_self_intersection: self.policy,
            ..*doc.print_setup()
        })?;
        Ok(OpOutcome::default())
    }
}

impl Apply for SetPrinter {
    const KIND: &'static str = "document";
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        doc.set_print_setup(PrintSetup {
            printer: Printer::new(self.printer, self.size)?,
            ..*doc.print_setup()
        })?;
        Ok(OpOutcome::default())
    }
}

/// Under [`SelfIntersectionPolicy::Refuse`], refuses the op that just made
/// object `id` pass through itself (`before`: its mesh before the edit,
/// `None` for a creation); the log then drops the op's copy of the
/// document, so nothing changes.
pub(super) fn check_fold(
    doc: &Document,
    id: ObjectId,
    before: Option<&Arc<TriMesh>>,
) -> Result<(), OpError> {
    if doc.print_setup().on_self_intersection != SelfIntersectionPolicy::Refuse {
        return Ok(());
    }
    let obj = doc.get(id)?;
    let label = format!("#{} {}", id.0, obj.kind.name());
    Ok(check_edit(&label, before.map(|b| &**b), &obj.mesh)?)
}
