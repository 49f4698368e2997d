//! The one printable path: every exit that writes a model for printing
//! (`apply --out`, `replay --stl`, `export`, the Blender export, the
//! headset's save) calls [`crate::doc::print_document`] (or [`printable`] on parts it
//! gathered itself) and writes the mesh it returns, or shows the error.
//!
//! What it does, in order (SPEC "Across all four": the printable model is
//! the boolean union of all objects as one closed 2-manifold; issue 17):
//! 1. **Gather** each object's mesh. An object with no triangles (a curve
//!    network with curves but no patches yet) is skipped and listed, so an
//!    unfinished network never blocks the rest. Non-finite coordinates and
//!    coordinates beyond [`PrintSettings::max_abs_coordinate`] are refused
//!    naming the object (a radius of `inf` that became 3.4e38 in Blender, a
//!    USD snapshot holding 1e39).
//! 2. **Make surfaces solid** ([`thicken`]): an open surface (any object
//!    whose mesh has a boundary: curve-network patches, an open sculpt base)
//!    becomes a shell of the document's wall thickness ([`PrintSetup`], set
//!    by the `set_wall_thickness` op; 2 mm by default), offset both ways from the surface (or inward or outward)
//!    with walls along its open boundaries. A closed curve network prints
//!    filled by default, or hollowed to the wall thickness
//!    ([`ClosedSurfaces`]).
//! 3. **Unite** every part with Manifold (`manifold-rust`), each imported at
//!    a snapping tolerance derived from the output precision: every edge
//!    shorter than it is collapsed and every sliver thinner than it swapped
//!    away, which is what nearly coincident, touching and duplicated-in-place
//!    parts leave behind.
//! 4. **Validate at the written precision**: the union rounded as the file
//!    stores it (float32 millimetres for STL and 3MF, float32 metres for
//!    PLY and USD points; exact metres for our OBJ) and
//!    welded as a reader welds it, then checked: non-empty, finite, in
//!    range, closed, oriented, no degenerate triangle, no pinched vertex,
//!    positive volume, no self-intersection (exact predicates). If rounding
//!    broke it, the union is re-snapped at 4, 16, 64 and 256 times the
//!    tolerance (at most 256 float32 steps of the largest coordinate: 3 µm
//!    on a part 10 cm from the origin) and validated again; if it is still
//!    invalid, the error names the objects whose triangles are at fault.
//!
//! **At edit time** ([`check_edit`]): GC and sculpt ops (the ones that can
//! fold an object through itself) are checked after they apply; under the
//! document's [`SelfIntersectionPolicy`] (`flag` by default, set by the
//! `set_self_intersection_policy` op) an edit that makes its object
//! intersect itself is refused with [`PrintError::SelfIntersecting`]; under
//! `flag` it applies and every print exit names the object.
//!
//! The result is the mesh as written (its coordinates, in metres, are
//! exactly the file's values converted back), with a [`PrintReport`]
//! listing what was done to each object, the tolerance used, every check
//! and the printed size ([`PrintedSize`]: bounding box in mm, volume in
//! cm³), which hosts hold against the document's printer ([`Printer`],
//! the `set_printer` op) to say whether and by how much it outgrows the
//! bed ([`BedFit`]). Choices and why:
//! - Snapping by Manifold's own clean-up (rather than our own welding) keeps
//!   the result a closed 2-manifold by construction; we only check it.
//! - The tolerance is relative to the largest coordinate, not the part's
//!   size, because that is what float32 rounding is relative to.
//! - Thickening uses angle-weighted vertex normals with a mitre factor
//!   (the offset grows as `1 / cos` of the angle to the incident faces,
//!   capped at 2), so creases keep the wall thickness up to 120 degrees.

mod control;
mod error;
mod fit;
mod pipeline;
mod report;
mod settings;
#[cfg(test)]
mod tests;
mod thicken;

pub use control::{PrintControl, PrintProgress, PrintStage};
pub use error::PrintError;
pub use fit::{
    floor_print_scale, mm3, BedFit, PrintStatus, PrintedSize, Printer, PrinterPreset, SetPrinter,
    MAX_BED_SIDE, MIN_BED_SIDE, MIN_PRINT_SCALE,
};
pub use pipeline::{check_edit, check_part, printable, printable_with, PrintPart, Printable};
pub use report::{PartReport, PrintReport, Treatment};
pub use settings::{
    ClosedSurfaces, PrintSettings, PrintSetup, SelfIntersectionPolicy, SetSelfIntersectionPolicy,
    SetWallThickness, ShellOffset, MAX_WALL_THICKNESS, MIN_WALL_THICKNESS,
};
pub use thicken::{thicken, ThickenError};
