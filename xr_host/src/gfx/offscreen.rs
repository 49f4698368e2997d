//! Offscreen rendering with pixel readback (PNG output, tests, the demo).

use std::sync::Arc;

use ash::vk;

use super::renderer::{GpuLines, MeshDraw, Renderer, ViewCamera, DEPTH_FORMAT};
use super::resource::{HostBuffer, LayeredImage};
use super::{GfxError, GpuContext};

/// sRGB color target: the shaders write linear values and the hardware
/// encodes, so the PNG bytes are display-ready.
pub const OFFSCREEN_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// Largest image side accepted (keeps a typo from allocating gigabytes).
pub const MAX_SIDE: u32 = 8192;

/// RGBA8 pixels of one view, row-major from the top-left.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

impl RgbaImage {
    /// The RGBA value at `(x, y)`, or None outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = ((y * self.width + x) * 4) as usize;
        self.pixels.get(i..i + 4).and_then(|s| s.try_into().ok())
    }
}

/// A color + depth target with `views` layers and a readback buffer.
pub struct OffscreenTarget {
    renderer: Renderer,
    color: LayeredImage,
    _depth: LayeredImage,
    framebuffer: super::renderer::Framebuffer,
    readback: HostBuffer,
    extent: vk::Extent2D,
}

impl OffscreenTarget {
    /// A `width`×`height` target with `views` layers (1 or 2).
    pub fn new(
        ctx: &Arc<GpuContext>,
        width: u32,
        height: u32,
        views: u32,
    ) -> Result<Self, GfxError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(GfxError::BadExtent { width, height });
        }
        let extent = vk::Extent2D { width, height };
        let renderer = Renderer::new(
            ctx,
            OFFSCREEN_FORMAT,
            views,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        )?;
        let color = LayeredImage::new(
            ctx,
            OFFSCREEN_FORMAT,
            extent,
            views,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
        )?;
        let depth = LayeredImage::new(
            ctx,
            DEPTH_FORMAT,
            extent,
            views,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?;
        let framebuffer = renderer.framebuffer(color.view(), depth.view(), extent)?;
        let readback = HostBuffer::new(
            ctx,
            u64::from(width) * u64::from(height) * 4 * u64::from(views),
            vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        Ok(Self {
            renderer,
            color,
            _depth: depth,
            framebuffer,
            readback,
            extent,
        })
    }

    /// The renderer (to upload meshes and lines).
    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }

    /// Renders one frame and reads every view back.
    pub fn render(
        &self,
        views: &[ViewCamera],
        clear: [f32; 4],
        meshes: &[MeshDraw<'_>],
        ui: Option<&GpuLines>,
        lines: Option<&GpuLines>,
    ) -> Result<Vec<RgbaImage>, GfxError> {
        self.renderer.set_views(views)?;
        let layers = self.renderer.view_count();
        let ctx = self.renderer.context();
        ctx.submit_and_wait(|dev, cmd| {
            self.renderer
                .record(cmd, &self.framebuffer, clear, meshes, ui, lines);
            let region = vk::BufferImageCopy {
                buffer_offset: 0,
                buffer_row_length: 0,
                buffer_image_height: 0,
                image_subresource: vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: layers,
                },
                image_offset: vk::Offset3D { x: 0, y: 0, z: 0 },
                image_extent: vk::Extent3D {
                    width: self.extent.width,
                    height: self.extent.height,
                    depth: 1,
                },
            };
            // SAFETY: the render pass left the color image in
            // TRANSFER_SRC_OPTIMAL (its final layout, with an external
            // dependency to TRANSFER); the buffer holds all layers.
            unsafe {
                dev.cmd_copy_image_to_buffer(
                    cmd,
                    self.color.image(),
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    self.readback.handle(),
                    &[region],
                );
                let barrier = vk::MemoryBarrier::default()
                    .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                    .dst_access_mask(vk::AccessFlags::HOST_READ);
                dev.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::PipelineStageFlags::HOST,
                    vk::DependencyFlags::empty(),
                    &[barrier],
                    &[],
                    &[],
                );
            }
        })?;
        let bytes = self.readback.read()?;
        let layer_bytes = (self.extent.width * self.extent.height * 4) as usize;
        Ok(bytes
            .chunks_exact(layer_bytes)
            .take(layers as usize)
            .map(|c| RgbaImage {
                width: self.extent.width,
                height: self.extent.height,
                pixels: c.to_vec(),
            })
            .collect())
    }
}
