//! The sculpt ops (paper 4): `sculpt_create` and `sculpt_stroke` applied to
//! a document's [`SculptMesh`]. Bases and brushes made from another
//! object's mesh get that mesh from the document as it is before the op.
//! Both are checked for folds after they apply (a warp that pushes the
//! surface through itself; see [`crate::print::check_edit`]).

use super::{EditCx, ObjectCreate, ObjectEdit};
use crate::doc::OpError;
use crate::sculpt::{SculptCreate, SculptMesh, SculptStroke};

impl ObjectCreate for SculptCreate {
    type Target = SculptMesh;
    const CHECK_FOLDS: bool = true;
    fn build(&self, cx: &mut EditCx<'_>) -> Result<SculptMesh, OpError> {
        let mesh = self.base.object().map(|id| cx.mesh(id)).transpose()?;
        Ok(SculptCreate::build(self, mesh)?)
    }
}

impl ObjectEdit for SculptStroke {
    type Target = SculptMesh;
    const CHECK_FOLDS: bool = true;
    fn apply(&self, target: &mut SculptMesh, cx: &mut EditCx<'_>) -> Result<(), OpError> {
        let mesh = self.brush_object().map(|id| cx.mesh(id)).transpose()?;
        Ok(self.apply_to(target, mesh)?)
    }
}
