//! [`CsgTool`]: the controller interface of paper 2 (EasyVRModeling §4)
//! over the `sdf_*` ops.
//!
//! The paper's eight modes on two 6-DOF controllers, adapted to the action
//! map of [`crate::interact::ActionMap`] (either hand works, as in the paper, except
//! where noted):
//!
//! | paper mode      | action                      | op                          |
//! |-----------------|-----------------------------|-----------------------------|
//! | select          | `select` (trigger) on a ray | — (selection)               |
//! | grab            | `grab` held on an operand   | `sdf_set_operand_transform` |
//! | scale (§4.3)    | both `grab` on one operand  | `sdf_scale_two_hand`        |
//! | scale axis      | right stick quadrant        | X (→), Y (↑), Z (←), A (↓)  |
//! | menu            | `menu`: right next, left previous | — (component)         |
//! | SceneOperate    | stick ↑/↓ picks, `primary` applies | `sdf_add_operand` / `sdf_cancel_operand` |
//! | update          | `secondary`                 | `sdf_update`                |
//! | copy (§4.4)     | `secondary` with an operand selected | `sdf_copy_operand` |
//! | delete          | double `select` on a target | `sdf_cancel_operand` / `delete` |
//! | undo / redo     | stick flick ← / →           | undo / redo                 |
//!
//! Choices:
//! - Paper 2 applies union / intersect / subtract to an operand already in
//!   the scene; here SceneOperate with a CSG operation places the menu's
//!   current component at the controller as a new pending operand with that
//!   operation (the op log's `sdf_add_operand` carries both), and *cancel*
//!   removes the selected pending operand.
//! - In a document without an SDF volume, SceneOperate creates one
//!   (`sdf_create`, one op for that press); the tool keeps working on the
//!   volume it found first while it exists, else on the newest one.
//! - As in the paper, copy is the update button with one operand selected;
//!   the copy is placed [`CsgToolSettings::copy_offset`] away.
//! - Operands are picked by their placed local bounding box (cheap every
//!   frame; the fused surface is picked by the document's mesh).
//! - Scaling starts when the second hand grabs the operand the first one
//!   holds (or the selected one): a drag in progress is committed first.
//!   The op stores both hands' model-space positions at start and end, so
//!   the ratio of Eq. 1 (clamped to `[0.4, 4]`) is recomputed by the op.
//!
//! - Palette "Grab moves: operand | fused result": with *fused result*,
//!   a grab on the fused surface drags the whole result (paper 2 §4.4's
//!   moving of a result as such); on release one `sdf_move_fused` carries
//!   the motion (a similarity in the volume's own frame). Pending operand
//!   boxes are not grabbed in that mode.
//! - Palette "Component from": every other object of the document; picking
//!   one is `sdf_component_from_object` (the object's closed mesh becomes a
//!   user component of the volume), and once applied that component is
//!   added to the "Component" menu and made the active one, so the next
//!   SceneOperate places it.
//!
//! Bad input during a drag or a scale: tracking lost → the preview
//! freezes and, after [`CsgToolSettings::grace`] s, the gesture is cancelled
//! (document unchanged); a teleport → the gesture is committed at its last
//! good state; NaN samples never reach the tool.

mod gestures;
mod settings;
mod tool;

#[cfg(test)]
pub(crate) use settings::MENU_LIBRARY;
pub use settings::{CsgToolSettings, SceneOperate};
pub use tool::CsgTool;
