//! The document's objects as [`PrintPart`]s: the one call every exit makes.
//! It lives with the document, above the printable path it calls
//! ([`crate::print`] knows parts and meshes, never the document).

use super::{Document, ObjectKind};
use crate::math::Transform;
use crate::mesh::{PartNames, TriMesh};
use crate::print::{
    printable_with, PrintControl, PrintError, PrintPart, PrintSettings, PrintStatus, Printable,
    PrintedSize,
};

/// Every object of `doc`, in id order, as a part to print. Curve networks
/// are surfaces; every other kind is a solid (an open mesh of any kind is
/// still thickened). An SDF volume's mesh is its fused result only: see
/// [`print_document`] for its queued operands.
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

/// The meshes of the SDF volumes that still have operands queued, with
/// those fused as the next `sdf_update` would fuse them (the document is
/// not changed), placed as their objects are: what the user placed and
/// sees as previews is what prints. A queue that cannot be fused is
/// refused naming the volume.
fn fused_pending(doc: &Document) -> Result<Vec<(u32, TriMesh)>, PrintError> {
    let mut out = Vec::new();
    for (id, obj) in doc.objects() {
        let ObjectKind::SdfVolume(v) = &obj.kind else {
            continue;
        };
        if v.pending.is_empty() {
            continue;
        }
        let refused = |why: String| PrintError::NotSolid {
            object: format!("#{} {}", id.0, obj.kind.name()),
            problems: format!(
                "its {} queued operand(s) cannot be fused: {why}",
                v.pending.len()
            ),
        };
        let mut mesh = v
            .updated()
            .and_then(|u| u.evaluate())
            .map_err(|e| refused(e.to_string()))?;
        if obj.placement != Transform::IDENTITY {
            let a = obj
                .placement
                .to_affine()
                .map_err(|e| refused(e.to_string()))?;
            mesh.transform(&a);
        }
        out.push((id.0, mesh));
    }
    Ok(out)
}

/// The printable model of `doc`: [`printable`] over [`document_parts`]
/// (SDF volumes with their queued operands fused), with the document's
/// wall thickness ([`Document::print_setup`]) in place of
/// `settings.wall_thickness`. Hosts write `Printable::mesh` in the format
/// whose precision they passed in `settings`, or show the error as it is.
pub fn print_document(doc: &Document, settings: &PrintSettings) -> Result<Printable, PrintError> {
    print_document_with(doc, settings, &PrintControl::default())
}

/// [`print_document`] with progress and cancelling ([`PrintControl`]).
pub fn print_document_with(
    doc: &Document,
    settings: &PrintSettings,
    control: &PrintControl,
) -> Result<Printable, PrintError> {
    let fused = fused_pending(doc)?;
    let mut parts = document_parts(doc);
    for part in &mut parts {
        if let Some((_, m)) = fused.iter().find(|(id, _)| *id == part.id) {
            part.mesh = m;
        }
    }
    printable_with(&parts, &doc.print_setup().apply_to(settings), control)
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
