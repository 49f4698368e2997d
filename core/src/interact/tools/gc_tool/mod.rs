//! The paper-1 hand-gesture tool (gc-assembly §4, Figure 10): create,
//! edit and manipulate generalized-cylinder assemblies with OPEN, FIST,
//! POINT and PINCH.
//!
//! - `settings`: thresholds and timings.
//! - `hand`: one hand's gesture, filtered ray, palm and pen.
//! - `target`: ray selection of a key point, section, part or empty space.
//! - `create`: sketch planes and the ops of creating and replacing.
//! - `edit`: the ops of drags, holds and pinches.
//! - `tool`: the state machine ([`GcTool`]).
//!
//! The puppet scripts of `tests/data/{mug,teapot}.trace.jsonl` are in
//! [`crate::interact::testkit`].

mod create;
#[cfg(test)]
pub(crate) mod drawn_tests;
mod edit;
mod hand;
mod settings;
mod state;
mod target;
#[cfg(test)]
pub(crate) mod tests;
mod tool;

pub use super::preview::{GcPreview, GcTarget};
pub use settings::GcToolSettings;
pub use tool::GcTool;
#[cfg(test)]
pub(crate) use tool::RESOLUTIONS;
