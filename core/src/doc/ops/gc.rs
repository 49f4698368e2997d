//! The generalized-cylinder ops (paper 1): `gc_create` and the part edits
//! of [`crate::gc::edits`], and the assembly edits of
//! [`crate::assembly::edit`], applied to a document's [`GcAssembly`].
//! Every one is checked for folds after it applies (a spine bent tighter
//! than its sections; see [`crate::print::check_edit`]).

use super::{EditCx, ObjectCreate, ObjectEdit};
use crate::assembly::{GcAddChild, GcCopy, GcEditPart, GcTransformPart};
use crate::doc::OpError;
use crate::gc::{self, GcAssembly};

impl ObjectCreate for gc::GcCreate {
    type Target = GcAssembly;
    const CHECK_FOLDS: bool = true;
    fn build(&self, _: &mut EditCx<'_>) -> Result<GcAssembly, OpError> {
        Ok(GcAssembly::single(gc::GcCreate::build(self)?))
    }
}

macro_rules! part_edits {
    ($($ty:ty),*) => {$(
        impl ObjectEdit for $ty {
            type Target = GcAssembly;
            const CHECK_FOLDS: bool = true;
            fn apply(&self, asm: &mut GcAssembly, _: &mut EditCx<'_>) -> Result<(), OpError> {
                Ok(gc::edit_part_gc(asm, self)?)
            }
        }
    )*};
}

part_edits!(
    gc::GcBend,
    gc::GcReplaceSpine,
    gc::GcResize,
    gc::GcShift,
    gc::GcTwist,
    gc::GcReplaceSection,
    gc::GcDeleteSection,
    gc::GcInsertSection,
    gc::GcSetShape,
    gc::GcSetResolution
);

macro_rules! assembly_edits {
    ($($ty:ty),*) => {$(
        impl ObjectEdit for $ty {
            type Target = GcAssembly;
            const CHECK_FOLDS: bool = true;
            fn apply(&self, asm: &mut GcAssembly, _: &mut EditCx<'_>) -> Result<(), OpError> {
                Ok(self.apply_to(asm)?)
            }
        }
    )*};
}

assembly_edits!(GcAddChild, GcCopy, GcTransformPart, GcEditPart);
