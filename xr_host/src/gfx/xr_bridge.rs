//! The unsafe edge between OpenXR and graphics: session creation (the
//! openxr crate marks it unsafe because the graphics binding's handles
//! must be valid).

use openxr as xr;

/// Creates an `XR_MND_headless` session (no graphics binding). The frame
/// waiter and stream are dropped: a headless loop makes no frame calls.
pub fn create_headless_session(
    instance: &xr::Instance,
    system: xr::SystemId,
) -> xr::Result<xr::Session<xr::Headless>> {
    // SAFETY: a headless session has no graphics handles to be valid; the
    // instance enabling XR_MND_headless is checked by the runtime, which
    // returns XR_ERROR_GRAPHICS_DEVICE_INVALID otherwise.
    let (session, _waiter, _stream) = unsafe {
        instance.create_session::<xr::Headless>(system, &xr::headless::SessionCreateInfo {})
    }?;
    Ok(session)
}

use std::sync::Arc;

use ash::vk;
use ash::vk::Handle as _;

use super::context::{graphics_queue_family, load_entry, with_device_info, VK_API_VERSION};
use super::renderer::{Framebuffer, Renderer, DEPTH_FORMAT};
use super::resource::{array_view, LayeredImage};
use super::{GfxError, GpuContext};

fn xr_err(what: &str, r: xr::sys::Result) -> GfxError {
    GfxError::Xr(format!("{what}: {r}"))
}

/// Creates the Vulkan instance and device through `XR_KHR_vulkan_enable2`
/// (the runtime picks the physical device and adds the extensions it
/// needs), with multiview enabled.
pub fn create_vulkan_for_openxr(
    instance: &xr::Instance,
    system: xr::SystemId,
) -> Result<Arc<GpuContext>, GfxError> {
    let reqs = instance
        .graphics_requirements::<xr::Vulkan>(system)
        .map_err(|r| xr_err("xrGetVulkanGraphicsRequirements2KHR", r))?;
    let want = xr::Version::new(1, 1, 0);
    if want < reqs.min_api_version_supported
        || want.major() > reqs.max_api_version_supported.major()
    {
        return Err(GfxError::Xr(format!(
            "the runtime needs Vulkan {}..{}.x, this host targets 1.1",
            reqs.min_api_version_supported,
            reqs.max_api_version_supported.major()
        )));
    }
    let entry = load_entry()?;
    let app = vk::ApplicationInfo::default()
        .application_name(c"shapewright-xr")
        .api_version(VK_API_VERSION);
    let info = vk::InstanceCreateInfo::default().application_info(&app);
    // SAFETY: ash's vkGetInstanceProcAddr has the C signature OpenXR
    // expects (transmuted between the two crates' identical fn types); the
    // create info lives across the call.
    let raw_instance = unsafe {
        instance.create_vulkan_instance(
            system,
            std::mem::transmute::<
                vk::PFN_vkGetInstanceProcAddr,
                xr::sys::platform::VkGetInstanceProcAddr,
            >(entry.static_fn().get_instance_proc_addr),
            &info as *const _ as *const _,
        )
    }
    .map_err(|r| xr_err("xrCreateVulkanInstanceKHR", r))?
    .map_err(|r| GfxError::vk("vkCreateInstance (via OpenXR)", vk::Result::from_raw(r)))?;
    // SAFETY: the runtime just created this instance with our entry's loader.
    let vk_instance = unsafe {
        ash::Instance::load(entry.static_fn(), vk::Instance::from_raw(raw_instance as _))
    };
    let destroy_instance = |e: GfxError| {
        // SAFETY: no device exists yet; nothing else owns the instance.
        unsafe { vk_instance.destroy_instance(None) };
        e
    };
    // SAFETY: the instance handle is live and was made for this system.
    let pdev =
        unsafe { instance.vulkan_graphics_device(system, vk_instance.handle().as_raw() as _) }
            .map_err(|r| destroy_instance(xr_err("xrGetVulkanGraphicsDevice2KHR", r)))?;
    let pdev = vk::PhysicalDevice::from_raw(pdev as _);
    let family = graphics_queue_family(&vk_instance, pdev)
        .ok_or(GfxError::NoDevice)
        .map_err(destroy_instance)?;
    let raw_device = with_device_info(family, |dinfo| {
        // SAFETY: as for the instance; `pdev` is the runtime's choice on it.
        unsafe {
            instance.create_vulkan_device(
                system,
                std::mem::transmute::<
                    vk::PFN_vkGetInstanceProcAddr,
                    xr::sys::platform::VkGetInstanceProcAddr,
                >(entry.static_fn().get_instance_proc_addr),
                pdev.as_raw() as _,
                dinfo as *const _ as *const _,
            )
        }
    })
    .map_err(|r| destroy_instance(xr_err("xrCreateVulkanDeviceKHR", r)))?
    .map_err(|r| {
        destroy_instance(GfxError::vk(
            "vkCreateDevice (via OpenXR)",
            vk::Result::from_raw(r),
        ))
    })?;
    // SAFETY: the runtime created this device on `pdev` of `vk_instance`.
    let device =
        unsafe { ash::Device::load(vk_instance.fp_v1_0(), vk::Device::from_raw(raw_device as _)) };
    // SAFETY: both handles are live, related, and handed over exactly once.
    let ctx = unsafe { GpuContext::from_raw_parts(entry, vk_instance, pdev, device, family) }?;
    Ok(Arc::new(ctx))
}

/// The session's graphics binding and frame protocol objects.
pub type VulkanSession = (
    xr::Session<xr::Vulkan>,
    xr::FrameWaiter,
    xr::FrameStream<xr::Vulkan>,
);

/// Creates a Vulkan session bound to `ctx`'s device and queue 0.
pub fn create_vulkan_session(
    instance: &xr::Instance,
    system: xr::SystemId,
    ctx: &GpuContext,
) -> xr::Result<VulkanSession> {
    let info = xr::vulkan::SessionCreateInfo {
        instance: ctx.instance().handle().as_raw() as _,
        physical_device: ctx.physical_device().as_raw() as _,
        device: ctx.device().handle().as_raw() as _,
        queue_family_index: ctx.queue_family(),
        queue_index: 0,
    };
    // SAFETY: the handles come from a live context created through this
    // instance and system (create_vulkan_for_openxr); the caller keeps the
    // context alive until the session is dropped.
    unsafe { instance.create_session::<xr::Vulkan>(system, &info) }
}

/// Framebuffers over an OpenXR swapchain's images (2-layer arrays), with a
/// depth buffer of our own. Views are destroyed on drop; the images belong
/// to the runtime.
pub struct SwapchainTargets {
    ctx: Arc<GpuContext>,
    views: Vec<vk::ImageView>,
    framebuffers: Vec<Framebuffer>,
    _depth: LayeredImage,
    /// Image size.
    pub extent: vk::Extent2D,
}

impl SwapchainTargets {
    /// Wraps the raw `images` of a swapchain created with `format`,
    /// `extent` and `renderer.view_count()` layers.
    pub fn new(
        renderer: &Renderer,
        images: &[u64],
        format: vk::Format,
        extent: vk::Extent2D,
    ) -> Result<Self, GfxError> {
        let ctx = renderer.context().clone();
        let layers = renderer.view_count();
        let depth = LayeredImage::new(
            &ctx,
            DEPTH_FORMAT,
            extent,
            layers,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?;
        let mut this = Self {
            ctx: ctx.clone(),
            views: Vec::new(),
            framebuffers: Vec::new(),
            _depth: depth,
            extent,
        };
        for &img in images {
            let view = array_view(
                &ctx,
                vk::Image::from_raw(img),
                format,
                layers,
                vk::ImageAspectFlags::COLOR,
            )?;
            this.views.push(view);
            let fb = renderer.framebuffer(view, this._depth.view(), extent)?;
            this.framebuffers.push(fb);
        }
        Ok(this)
    }

    /// The framebuffer of swapchain image `index`.
    pub fn framebuffer(&self, index: u32) -> Option<&Framebuffer> {
        self.framebuffers.get(index as usize)
    }
}

impl Drop for SwapchainTargets {
    fn drop(&mut self) {
        self.framebuffers.clear();
        // SAFETY: the views were created on this device; the frame that
        // used them was waited for (submit_and_wait) before we get here.
        unsafe {
            let _ = self.ctx.device().device_wait_idle();
            for v in self.views.drain(..) {
                self.ctx.device().destroy_image_view(v, None);
            }
        }
    }
}
