//! The document's objects as [`PrintPart`]s: the one call every exit makes.
//! It lives with the document, above the printable path it calls
//! ([`crate::print`] knows parts and meshes, never the document).

use super::{Document, ObjectKind};
use crate::math::Transform;
use crate::mesh::{PartNames, TriMesh};
use crate::print::{
    floor_print_scale, printable_with, BedFit, PrintControl, PrintError, PrintPart, PrintSettings,
    PrintStatus, Printable, PrintedSize, MIN_PRINT_SCALE,
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

/// The printable model of `doc`: [`printable`](crate::print::printable) over [`document_parts`]
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

/// The size a print is made at, as a host's export asks for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PrintScale {
    /// This factor about the origin (1: true size;
    /// [`PrintSettings::scale`]).
    By(f64),
    /// Down to fit the document's printer, or true size when it fits
    /// ([`BedFit::print_scale`]).
    ToFit,
}

/// A print made at a [`PrintScale`].
#[derive(Debug)]
pub struct ScaledPrint {
    /// The printable model, at [`ScaledPrint::scale`].
    pub printable: Printable,
    /// The factor it was printed at.
    pub scale: f64,
    /// For [`PrintScale::ToFit`] of a model too big at true size: how
    /// it fits at true size (the sentence a host shows with the scale).
    pub too_big: Option<BedFit>,
}

impl ScaledPrint {
    /// What a host says when [`PrintScale::ToFit`] scaled the model down:
    /// `scaled to 5.4% to fit the Prusa MK4 (250 x 210 x 220 mm); at true
    /// size it is too big by x 2662.4 mm, ...`. `None` at true size.
    pub fn scaled_line(&self) -> Option<String> {
        self.too_big.map(|f| {
            format!(
                "scaled to {:.1}% to fit the {}; at true size it is {}",
                self.scale * 100.0,
                f.printer.describe(),
                f.overhang()
            )
        })
    }
}

/// [`print_document_with`] at `scale` (in place of `settings.scale`).
///
/// [`PrintScale::ToFit`] takes the scale from the objects' box
/// ([`document_size`]) and then checks the printed model: an open
/// surface's wall keeps its thickness at any scale, so a model scaled to
/// the bed's edge can come out up to a wall too big. Then the scale
/// shrinks by what the printed model overhangs, floored to 0.1% again, and
/// the model is printed once more (at most [`FIT_RETRIES`] times; after
/// that the print is returned as it is and its report's size says it does
/// not fit).
pub fn print_document_scaled(
    doc: &Document,
    settings: &PrintSettings,
    scale: PrintScale,
    control: &PrintControl,
) -> Result<ScaledPrint, PrintError> {
    let at = |s: f64| {
        let settings = PrintSettings {
            scale: s,
            ..*settings
        };
        print_document_with(doc, &settings, control)
    };
    if let PrintScale::By(s) = scale {
        return Ok(ScaledPrint {
            printable: at(s)?,
            scale: s,
            too_big: None,
        });
    }
    let printer = doc.print_setup().printer;
    let too_big = document_size(doc)
        .map(|size| size.fit(&printer))
        .filter(|f| !f.fits);
    let mut s = too_big.map_or(1.0, |f| f.print_scale());
    let mut printable = at(s)?;
    // A model whose box fits but whose walls do not is too big as printed:
    // that is the fit its scale sentence reports.
    let mut too_big = too_big;
    for _ in 0..FIT_RETRIES {
        let Some(fit) = printable.report.size().map(|size| size.fit(&printer)) else {
            break;
        };
        if fit.fits || s <= MIN_PRINT_SCALE {
            break;
        }
        too_big = too_big.or(Some(fit));
        s = floor_print_scale(s * fit.scale_to_fit);
        printable = at(s)?;
    }
    Ok(ScaledPrint {
        printable,
        scale: s,
        too_big,
    })
}

/// How often [`print_document_scaled`] shrinks a fitted print that its
/// walls pushed over the bed.
pub const FIT_RETRIES: usize = 3;

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
