//! `shapewright-xr` as a library: the Vulkan renderer ([`gfx`], the only
//! module with `unsafe`), crash-safe file writes ([`files`]), progress for long commands ([`progress`]), offscreen rendering to PNG ([`render`]), the
//! OpenXR host ([`xr`]), and the interaction step the frame loops and
//! `replay` share ([`interaction`]). The binary's subcommands call into these.

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
