//! The SDF CSG ops (paper 2): the payloads of [`crate::sdf::edits`]
//! applied to a document's [`SdfVolume`], named by the field `volume`.

use super::{EditCx, ObjectCreate, ObjectEdit};
use crate::doc::{ObjectKind, OpError};
use crate::sdf::{self, SdfVolume};

impl ObjectCreate for sdf::SdfCreate {
    type Target = SdfVolume;
    fn build(&self, _: &mut EditCx<'_>) -> Result<SdfVolume, OpError> {
        Ok(sdf::SdfCreate::build(self)?)
    }
}

macro_rules! volume_edits {
    ($($ty:ty),*) => {$(
        impl ObjectEdit for $ty {
            type Target = SdfVolume;
            const ID_FIELD: &'static str = "volume";
            fn apply(&self, v: &mut SdfVolume, _: &mut EditCx<'_>) -> Result<(), OpError> {
                Ok(self.apply_to(v)?)
            }
        }
    )*};
}

volume_edits!(
    sdf::SdfAddOperand,
    sdf::SdfSetOperandTransform,
    sdf::SdfScaleTwoHand,
    sdf::SdfCancelOperand,
    sdf::SdfCopyOperand,
    sdf::SdfUpdate,
    sdf::SdfImportComponent,
    sdf::SdfSetStep,
    sdf::SdfMoveFused,
    sdf::SdfCopyFused
);

/// The object's mesh is read from the document before the op, taken into
/// the volume's own frame (its placement inverted); a volume made a
/// component keeps its own step when it is finer.
impl ObjectEdit for sdf::SdfComponentFromObject {
    type Target = SdfVolume;
    const ID_FIELD: &'static str = "volume";
    fn apply(&self, v: &mut SdfVolume, cx: &mut EditCx<'_>) -> Result<(), OpError> {
        let placement = cx.target_placement()?.to_affine()?;
        let source = cx.doc.get(self.object)?;
        let source_step = match &source.kind {
            ObjectKind::SdfVolume(s) => Some(
                source
                    .transform()
                    .scale
                    .iter()
                    .fold(s.step, |m, x| m.min(s.step * x.abs())),
            ),
            _ => None,
        };
        let mesh = cx.mesh(self.object)?;
        let work = mesh.triangles.len() as u64;
        self.apply_to(v, mesh, &placement, source_step)?;
        cx.add_work(work);
        Ok(())
    }
}
