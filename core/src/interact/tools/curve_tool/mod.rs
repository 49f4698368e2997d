//! [`CurveNetworkTool`]: the controller interface of paper 3 (variational
//! curve styling, §6): draw curves in space, edit them with the smoother,
//! sharpener and puller chosen by the pointer pose (Table 1), fill loops,
//! undo and redo. Registered for traces as `"curve"`.
//!
//! The dominant hand (right by default) holds the pen; its tip is the aim
//! pose's position plus [`CurveToolSettings::tip_offset`] along the aim.
//! The other hand holds a plane.
//!
//! | input (dominant hand)   | action                                      |
//! |-------------------------|---------------------------------------------|
//! | trigger held            | draw, or apply the tool chosen at the press |
//! | `primary` (A)           | fill every loop found (`curve_fill_auto`), or the pointed loop (`curve_fill_loop`) when the palette says so |
//! | `secondary` (B)         | delete the pointed curve (Table 1 bands)    |
//! | stick flick ← / → (either hand) | undo / redo                         |
//!
//! | input (other hand)      | plane (through the grip, normal = its aim)  |
//! |-------------------------|---------------------------------------------|
//! | `grab` held at the press | drawing plane: samples are projected on it |
//! | trigger held at the press | symmetry plane: the stroke is mirrored    |
//!
//! At the trigger's press edge, [`crate::styling::select::select_in_network`]
//! applies Table 1 to the curve nearest to the tip: `d < 2 cm` and the
//! pointer across the curve (60°..120°) pulls the pointed point (puller),
//! `2..4 cm` across sharpens, `2..4 cm` along (≤ 30° or ≥ 150°) smooths. The
//! choice holds until release. Anything else (attach: `d < 2 cm` along;
//! far away; between the angle bands) draws a new curve, which the network
//! snaps to the curves it passes within [`CurveToolSettings::snap_tol`].
//! The palette's "Trigger" group can force one tool instead ("auto" is
//! Table 1). Forced smooth, sharpen and pull act on the pointed *surface*
//! (paper 3 §4: `surface_smooth`, `surface_sharpen`, `surface_pull` at the
//! pointed `(u0, v0)`) when a patch is at least [`SURFACE_MARGIN`] nearer
//! to the tip than any curve, and on the nearest curve otherwise; "auto"
//! never edits a surface, so a stroke started over a patch still draws.
//! Forced "attract" draws the pointed curve towards what the other hand
//! holds at the press (§2.2, `curve_attract`, local around the pointed
//! point): its grip point, the line along its aim when its trigger is
//! held, the plane through its grip normal to its aim when its grip is
//! held; one frame of attraction per frame held.
//!
//! Each held application is one op carrying its sampled path: `curve_draw`
//! with the tip samples (model space, at least `min_spacing` apart),
//! `curve_pull` / `curve_smooth` / `curve_sharpen` with the tip per frame.
//! The first press with no network in the document emits
//! `curve_network_create` (the stroke goes on; its curve goes to the new
//! network at release). A mirrored stroke is a second `curve_draw` on the
//! next frame (at most one command per frame). The planes are taken at the
//! press and held for the stroke, so a wobbling hand does not bend it.
//!
//! Bad input during a stroke (as [`crate::interact::ObjectTool`]): NaN poses never
//! reach the tool (the sanitizer drops them; the frame adds no sample);
//! tracking lost freezes the stroke and cancels it (nothing emitted) after
//! [`CurveToolSettings::grace`] seconds; a teleport commits the stroke as
//! it was before the jump.
//!
//! Preview each frame: the pen ray, the sketch being drawn (model space),
//! and [`CurvePreview`] (the mode the trigger would start or is running,
//! the pointed curve point, the planes, the held path).

mod modes;
mod settings;
mod tool;

pub use super::preview::{
    CurveMode, CurvePreview, CurveTarget, DrawPlane, PatchTarget, SurfaceTool,
};
pub use modes::SURFACE_MARGIN;
pub use settings::CurveToolSettings;
pub use tool::CurveNetworkTool;
