//! The generalized-cylinder ops (paper 1): `gc_create` and the part edits
//! of [`crate::gc::edits`], and the assembly edits of
//! [`crate::assembly::edits`], applied to a document's [`GcAssembly`].
//! Every part edit goes through the one structure-aware path
//! ([`crate::assembly::propagate_edit`]: symmetry group, then descendants
//! breadth-first, then the recorded relations are checked).
//! Every one is estimated in seconds before it is evaluated
//! ([`crate::gc::budget::check_edit`]) and checked for folds after it
//! applies (a spine bent tighter than its sections; see
//! [`crate::print::check_edit`]).

use super::{EditCx, ObjectCreate, ObjectEdit};
use crate::assembly::{
    propagate_edit, AssemblyError, GcAddChild, GcCopy, GcEditPart, GcRelease, GcTransformPart,
};
use crate::doc::OpError;
use crate::gc::{self, GcAssembly};

impl ObjectCreate for gc::GcCreate {
    type Target = GcAssembly;
    const CHECK_FOLDS: bool = true;
    fn build(&self, _: &mut EditCx<'_>) -> Result<GcAssembly, OpError> {
        let asm = GcAssembly::single(gc::GcCreate::build(self)?);
        gc::budget::check_edit(None, &asm)?;
        Ok(asm)
    }
}

/// A GC error inside an assembly op stays a GC error (as the union's do).
fn gc_error(e: AssemblyError) -> OpError {
    match e {
        AssemblyError::Gc(g) => OpError::Gc(g),
        other => OpError::Assembly(other),
    }
}

/// Applies `edit` to `asm`, then holds the result to the GC time budget
/// against the assembly as it was.
fn budgeted(
    asm: &mut GcAssembly,
    edit: impl FnOnce(&mut GcAssembly) -> Result<(), AssemblyError>,
) -> Result<(), OpError> {
    let before = asm.clone();
    edit(asm).map_err(gc_error)?;
    Ok(gc::budget::check_edit(Some(&before), asm)?)
}

macro_rules! part_edits {
    ($($ty:ty),*) => {$(
        impl ObjectEdit for $ty {
            type Target = GcAssembly;
            const CHECK_FOLDS: bool = true;
            fn apply(&self, asm: &mut GcAssembly, _: &mut EditCx<'_>) -> Result<(), OpError> {
                budgeted(asm, |a| propagate_edit(a, self))
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
                budgeted(asm, |a| self.apply_to(a))
            }
        }
    )*};
}

assembly_edits!(GcAddChild, GcCopy, GcTransformPart, GcEditPart, GcRelease);
