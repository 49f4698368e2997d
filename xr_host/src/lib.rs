//! `shapewright-xr` as a library: the Vulkan renderer ([`gfx`], the only
//! module with `unsafe`), offscreen rendering to PNG ([`render`]), and the
//! OpenXR host ([`xr`]). The binary's subcommands call into these.

#![deny(unsafe_code)]

#[allow(unsafe_code)]
pub mod gfx;
pub mod render;
pub mod sdf_store;
pub mod xr;
