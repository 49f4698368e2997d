//! Vulkan through `ash` (libvulkan loaded at run time): the only place
//! with `unsafe` in this crate. Every raw handle is wrapped in a type that
//! destroys it on drop, and every `unsafe` block says why it is sound.
//!
//! Choices: host-visible buffers (simple, enough for interactive meshes,
//! and all memory is host memory on lavapipe); one multiview render pass
//! for both eyes (`VK_KHR_multiview`, core in 1.1); SPIR-V precompiled
//! from the GLSL in `xr_host/shaders/` and committed.

mod context;
pub mod hud;
mod offscreen;
mod renderer;
mod resource;
mod scene;
pub mod text;
pub mod xr_raw;

pub use context::{GpuContext, VK_API_VERSION};
pub use offscreen::{OffscreenTarget, RgbaImage, OFFSCREEN_FORMAT};
pub use renderer::{
    Framebuffer, GpuLines, GpuMesh, LineVertex, MeshDraw, Renderer, ViewCamera, DEPTH_FORMAT,
};
pub mod xr_bridge;
pub use resource::{array_view, HostBuffer, LayeredImage};
pub use scene::Scene;

mod error;

pub use error::GfxError;
