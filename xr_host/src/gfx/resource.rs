//! Buffers and images with their memory, destroyed on drop.

use std::sync::Arc;

use ash::vk;

use super::{GfxError, GpuContext};

/// A host-visible, host-coherent buffer (vertex, index, uniform or
/// readback). Everything this host draws is small enough that device-local
/// staging would cost more code than it saves, and on lavapipe all memory
/// is host memory anyway.
pub struct HostBuffer {
    ctx: Arc<GpuContext>,
    buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    size: u64,
}

impl HostBuffer {
    /// A buffer of `size` bytes (at least 1) for `usage`.
    pub fn new(
        ctx: &Arc<GpuContext>,
        size: u64,
        usage: vk::BufferUsageFlags,
    ) -> Result<Self, GfxError> {
        let size = size.max(1);
        let dev = ctx.device();
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: live device; the buffer is destroyed in Drop (or below on error).
        let buffer = unsafe { dev.create_buffer(&info, None) }
            .map_err(|r| GfxError::vk("vkCreateBuffer", r))?;
        // SAFETY: `buffer` was created on `dev`.
        let req = unsafe { dev.get_buffer_memory_requirements(buffer) };
        let memory = ctx.allocate(
            req,
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
        );
        let memory = match memory {
            Ok(m) => m,
            Err(e) => {
                // SAFETY: the buffer is unused.
                unsafe { dev.destroy_buffer(buffer, None) };
                return Err(e);
            }
        };
        let this = Self {
            ctx: ctx.clone(),
            buffer,
            memory,
            size,
        };
        // SAFETY: memory type allowed by the buffer's requirements, offset 0.
        unsafe { dev.bind_buffer_memory(buffer, memory, 0) }
            .map_err(|r| GfxError::vk("vkBindBufferMemory", r))?;
        Ok(this)
    }

    /// A buffer holding `data`.
    pub fn with_data<T: Copy>(
        ctx: &Arc<GpuContext>,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self, GfxError> {
        let b = Self::new(ctx, std::mem::size_of_val(data) as u64, usage)?;
        b.write(0, data)?;
        Ok(b)
    }

    /// The raw handle.
    pub fn handle(&self) -> vk::Buffer {
        self.buffer
    }

    /// Size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Copies `data` into the buffer at byte `offset`.
    pub fn write<T: Copy>(&self, offset: u64, data: &[T]) -> Result<(), GfxError> {
        let bytes = std::mem::size_of_val(data) as u64;
        if offset + bytes > self.size {
            return Err(GfxError::BufferOverflow {
                needed: offset + bytes,
                size: self.size,
            });
        }
        if bytes == 0 {
            return Ok(());
        }
        let dev = self.ctx.device();
        // SAFETY: host-visible memory, range checked above; the GPU is not
        // using this range (callers write before submit or after a fence).
        unsafe {
            let p = dev
                .map_memory(self.memory, offset, bytes, vk::MemoryMapFlags::empty())
                .map_err(|r| GfxError::vk("vkMapMemory", r))?;
            std::ptr::copy_nonoverlapping(data.as_ptr() as *const u8, p as *mut u8, bytes as usize);
            dev.unmap_memory(self.memory);
        }
        Ok(())
    }

    /// Reads the whole buffer.
    pub fn read(&self) -> Result<Vec<u8>, GfxError> {
        let dev = self.ctx.device();
        let mut out = vec![0u8; self.size as usize];
        // SAFETY: host-visible coherent memory of `size` bytes; called after
        // the GPU work that wrote it completed (fence waited).
        unsafe {
            let p = dev
                .map_memory(self.memory, 0, self.size, vk::MemoryMapFlags::empty())
                .map_err(|r| GfxError::vk("vkMapMemory", r))?;
            std::ptr::copy_nonoverlapping(p as *const u8, out.as_mut_ptr(), out.len());
            dev.unmap_memory(self.memory);
        }
        Ok(out)
    }
}

impl Drop for HostBuffer {
    fn drop(&mut self) {
        // SAFETY: created on this device; callers wait for GPU work using it
        // before dropping (submit_and_wait, or the frame fence).
        unsafe {
            self.ctx.device().destroy_buffer(self.buffer, None);
            self.ctx.device().free_memory(self.memory, None);
        }
    }
}

/// A device-local 2D array image (one layer per view) with a view over all
/// layers.
pub struct LayeredImage {
    ctx: Arc<GpuContext>,
    image: vk::Image,
    memory: vk::DeviceMemory,
    view: vk::ImageView,
}

impl LayeredImage {
    /// An image of `format` and `extent` with `layers` layers.
    pub fn new(
        ctx: &Arc<GpuContext>,
        format: vk::Format,
        extent: vk::Extent2D,
        layers: u32,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self, GfxError> {
        let dev = ctx.device();
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(layers)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: live device; destroyed in Drop or below on error.
        let image = unsafe { dev.create_image(&info, None) }
            .map_err(|r| GfxError::vk("vkCreateImage", r))?;
        // SAFETY: `image` was created on `dev`.
        let req = unsafe { dev.get_image_memory_requirements(image) };
        let memory = match ctx.allocate(req, vk::MemoryPropertyFlags::DEVICE_LOCAL) {
            Ok(m) => m,
            Err(e) => {
                // SAFETY: unused image.
                unsafe { dev.destroy_image(image, None) };
                return Err(e);
            }
        };
        // SAFETY: allowed memory type, offset 0, image not yet bound.
        let bound = unsafe { dev.bind_image_memory(image, memory, 0) };
        let view = bound
            .map_err(|r| GfxError::vk("vkBindImageMemory", r))
            .and_then(|_| array_view(ctx, image, format, layers, aspect));
        match view {
            Ok(view) => Ok(Self {
                ctx: ctx.clone(),
                image,
                memory,
                view,
            }),
            Err(e) => {
                // SAFETY: unused image and memory.
                unsafe {
                    dev.destroy_image(image, None);
                    dev.free_memory(memory, None);
                }
                Err(e)
            }
        }
    }

    /// The raw image.
    pub fn image(&self) -> vk::Image {
        self.image
    }
    /// The view over all layers.
    pub fn view(&self) -> vk::ImageView {
        self.view
    }
}

impl Drop for LayeredImage {
    fn drop(&mut self) {
        // SAFETY: created on this device; GPU work using it has completed.
        unsafe {
            let dev = self.ctx.device();
            dev.destroy_image_view(self.view, None);
            dev.destroy_image(self.image, None);
            dev.free_memory(self.memory, None);
        }
    }
}

/// A 2D-array view over `layers` layers of `image`.
pub fn array_view(
    ctx: &GpuContext,
    image: vk::Image,
    format: vk::Format,
    layers: u32,
    aspect: vk::ImageAspectFlags,
) -> Result<vk::ImageView, GfxError> {
    let info = vk::ImageViewCreateInfo::default()
        .image(image)
        .view_type(vk::ImageViewType::TYPE_2D_ARRAY)
        .format(format)
        .subresource_range(vk::ImageSubresourceRange {
            aspect_mask: aspect,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: layers,
        });
    // SAFETY: `image` is a live image of this device with at least `layers` layers.
    unsafe { ctx.device().create_image_view(&info, None) }
        .map_err(|r| GfxError::vk("vkCreateImageView", r))
}
