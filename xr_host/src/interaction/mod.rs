//! The interaction step both frame loops (headset, headless) and `replay`
//! run: one raw [`shapewright::interact::InputFrame`] in, a
//! [`shapewright::interact::Session`] stepped against the latest document,
//! and the [`Scene`](crate::gfx::Scene) (document mesh, drag preview, rays and sketch)
//! brought up to date for the renderer.
//!
//! **Commits run off the frame.** A command the tool produces is handed
//! to a commit thread that owns the [`OpLog`](shapewright::doc::OpLog): applying an op re-evaluates
//! its object (a generalized-cylinder assembly re-unites all its parts,
//! 70 to 160 ms for the teapot), which would drop several 90 Hz frames.
//! The scene keeps being drawn every frame; the tool's input frames are
//! held while a command of its own is being committed and stepped, in
//! order, against the document that command made once it is in, so the
//! tool never acts on a document older than its own commands (a grab
//! right after a duplicate grabs the copy on however slow a machine), and
//! a live session (outside a shared one, where others' edits arrive on
//! their own schedule) does exactly what the core's
//! [`shapewright::interact::replay`] of its recorded input does, bit for
//! bit. The head, hands and controllers are drawn from the newest frame
//! meanwhile. Commands are applied strictly in the order they were produced.
//! [`Interaction::flush`] steps every held frame and waits for every
//! commit: `replay` calls it after each frame (the same result, sooner).
//!
//! Persistence: an optional [`Autosaver`](shapewright_usd::Autosaver) on the commit thread saves the
//! log as USD (with its history, so `run --open` continues it and undo
//! works) every N changes or T seconds, and [`Interaction::save_now`] is
//! called on session loss, instance loss and exit; it saves after every
//! command produced before it, so no acknowledged op is lost. A failed
//! save is reported (stderr, [`InteractionStats::save_errors`], and a red
//! message in the headset until a save succeeds) and retried at the next
//! trigger; it never stops the session, and the file on disk keeps the
//! last good save (the autosaver replaces it atomically), so a failure
//! loses at most the ops since then.
//!
//! Shared sessions (`run --join`): the commit thread also owns the
//! session's [`shapewright_net::Link`]. It pumps it every few milliseconds
//! (others' entries in, this person's appends out) and hands the frame a
//! new document when others' edits arrived, exactly as after a local
//! commit; the headset says when the server is out of reach and shows the
//! refusals the session sends this person.
//!
//! Haptics: a short pulse on the hand(s) that made a command when its
//! commit lands (the hands holding a button in the frame that produced
//! it, else both), and a tick when a ray starts pointing at something.
//!
//! Tools come from [`shapewright::interact::tool_named`], so every tool the core
//! registers is available to `--tool` without a list here.

mod commit;
mod frame;
mod presence;
mod sink;
#[cfg(test)]
mod tests;

pub use commit::LogGuard;
pub use frame::{Interaction, InteractionError, InteractionStats};
