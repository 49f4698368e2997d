//! Where a child part sits on its parent, as the GC model stores it
//! ([`Anchor`], [`Attachment`]). The data lives here, a floor below the assembly
//! module that computes it (projection and frames in
//! [`crate::assembly`]), so the model names nothing above it.

use serde::{Deserialize, Serialize};

/// A point of a parent's side surface `S(u, v)` (`u` around the sections,
/// `v` the spine parameter).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Anchor {
    /// Parameter around the section.
    pub u: f64,
    /// Spine parameter.
    pub v: f64,
}

/// How a child is attached to its parent: its spine starts at `start`,
/// and a handle's spine also ends at `end` (a spout's end is free).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Attachment {
    /// Anchor of the spine's start (the picked point).
    pub start: Anchor,
    /// Anchor of the spine's end, for a handle.
    pub end: Option<Anchor>,
}
