//! `shapewright-xr` as a library: the Vulkan renderer ([`gfx`], the only
//! module with `unsafe`), crash-safe file writes ([`files`]), progress for long commands ([`progress`]), offscreen rendering to PNG ([`render`]), the
//! OpenXR host ([`xr`]), and the interaction step the frame loops and
//! `replay` share ([`interaction`]). The binary's subcommands call into these.
//!
//! Float math (issue 32): transcendental functions go through
//! `shapewright::math::fm::DetMath` (`x.fsin()`) here too, `clippy.toml`
//! disallows std's. Rendering that only feeds the headset ([`gfx`]'s
//! frame loop) never reaches the document and may use std's with
//! `#[allow(clippy::disallowed_methods)]` and a line saying so; nothing
//! needs it today, and `render` and `replay --png` write PNGs that the
//! Windows test compares byte for byte, so their camera and shading use
//! `DetMath` as well.

#![deny(unsafe_code)]

pub mod files;
#[allow(unsafe_code)]
pub mod gfx;
pub mod interaction;
pub mod progress;
pub mod render;
pub mod sdf_store;
pub mod ui;
pub mod xr;
