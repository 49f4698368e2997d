//! The document's objects as [`PrintPart`]s: the one call every exit makes.

use super::{
    printable_with, PrintControl, PrintError, PrintPart, PrintSettings, PrintStatus, Printable,
    PrintedSize,
};
use crate::doc::{Document, ObjectKind};
use crate::mesh::PartNames;

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

/// Every object's name for files that name parts (3MF): its user name, or
/// `kind id` when it has none (`gc_assembly 3`).
pub fn document_names(doc: &Document) -> PartNames {
    doc.objects()
        .map(|(id, obj)| {
            let name = if obj.name.trim().is_empty() {
                format!("{} {}", obj.kind.name(), id.0)
            } else {
                obj.name.clone()
            };
            (id.0, name)
        })
        .collect()
}

/// The bounding box of every object's mesh, without the union (what a
/// host shows after each edit: the printable union's box is the same
/// except for open surfaces, whose wall adds up to its thickness). No
/// volume: that needs the union ([`print_document`]). `None` for a
/// document with no triangles.
pub fn document_size(doc: &Document) -> Option<PrintedSize> {
    let mut bbox: Option<[[f64; 3]; 2]> = None;
    for (_, obj) in doc.objects() {
        if let Some((lo, hi)) = obj.mesh.bbox() {
            let (lo, hi) = (lo.to_array(), hi.to_array());
            bbox = Some(match bbox {
                None => [lo, hi],
                Some([a, b]) => [
                    [0, 1, 2].map(|k| a[k].min(lo[k])),
                    [0, 1, 2].map(|k| b[k].max(hi[k])),
                ],
            });
        }
    }
    bbox.map(|b| PrintedSize::new(b, None))
}

/// What a host shows after each edit: the objects' size ([`document_size`])
/// against the document's printer. `None` for a document with nothing to
/// print yet.
pub fn print_status(doc: &Document) -> Option<PrintStatus> {
    let size = document_size(doc)?;
    Some(PrintStatus {
        size,
        fit: size.fit(&doc.print_setup().printer),
    })
}
