//! The document's objects as [`PrintPart`]s: the one call every exit makes.

use super::{printable_with, PrintControl, PrintError, PrintPart, PrintSettings, Printable};
use crate::doc::{Document, ObjectKind};

/// Every object of `doc`, in id order, as a part to print. Curve networks
/// are surfaces; every other kind is a solid (an open mesh of any kind is
/// still thickened).
pub fn document_parts(doc: &Document) -> Vec<PrintPart<'_>> {
    doc.objects()
        .map(|(id, obj)| PrintPart {
            id: id.0,
            kind: obj.kind.name(),
            surface: matches!(obj.kind, ObjectKind::CurveNetwork(_)),
            mesh: &obj.mesh,
        })
        .collect()
}

/// The printable model of `doc`: [`printable`] over [`document_parts`],
/// with the document's wall thickness ([`Document::print_setup`]) in place
/// of `settings.wall_thickness`. Hosts write `Printable::mesh` in the
/// format whose precision they passed in `settings`, or show the error as
/// it is.
pub fn print_document(doc: &Document, settings: &PrintSettings) -> Result<Printable, PrintError> {
    print_document_with(doc, settings, &PrintControl::default())
}

/// [`print_document`] with progress and cancelling ([`PrintControl`]).
pub fn print_document_with(
    doc: &Document,
    settings: &PrintSettings,
    control: &PrintControl,
) -> Result<Printable, PrintError> {
    printable_with(
        &document_parts(doc),
        &doc.print_setup().apply_to(settings),
        control,
    )
}
