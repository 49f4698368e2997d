//! The Vulkan context: instance, physical device, logical device, one
//! graphics queue and a command pool, owned together and destroyed in
//! reverse order on drop.
//!
//! Two ways in: [`GpuContext::new_offscreen`] creates everything itself
//! (lavapipe or any Vulkan 1.1 device), and [`GpuContext::from_raw_parts`]
//! adopts an instance and device that OpenXR's `XR_KHR_vulkan_enable2`
//! created for the headset session.

use std::ffi::CStr;

use ash::vk;

use super::GfxError;

/// Vulkan 1.1: multiview is core there, which the stereo path needs.
pub const VK_API_VERSION: u32 = vk::make_api_version(0, 1, 1, 0);

/// Owns the Vulkan instance and device; every other GPU object holds an
/// `Arc<GpuContext>` so it is destroyed before the device.
pub struct GpuContext {
    entry: ash::Entry,
    instance: ash::Instance,
    physical_device: vk::PhysicalDevice,
    device: ash::Device,
    queue: vk::Queue,
    queue_family: u32,
    command_pool: vk::CommandPool,
    memory_properties: vk::PhysicalDeviceMemoryProperties,
    device_name: String,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext")
            .field("device_name", &self.device_name)
            .field("queue_family", &self.queue_family)
            .finish()
    }
}

/// Loads `libvulkan` at run time.
pub fn load_entry() -> Result<ash::Entry, GfxError> {
    // SAFETY: loading the system Vulkan loader runs its initialisers; it is
    // the documented way to use ash's `loaded` feature, and the entry is kept
    // alive for as long as any handle derived from it (it lives in GpuContext).
    unsafe { ash::Entry::load() }.map_err(|e| GfxError::LoadVulkan(e.to_string()))
}

/// The first queue family of `pdev` that supports graphics.
pub fn graphics_queue_family(instance: &ash::Instance, pdev: vk::PhysicalDevice) -> Option<u32> {
    // SAFETY: `pdev` was enumerated from `instance`, which is alive.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pdev) };
    families
        .iter()
        .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
        .map(|i| i as u32)
}

impl GpuContext {
    /// Creates an instance and device of its own, for offscreen rendering.
    /// Prefers a discrete, then integrated GPU, then a CPU device (lavapipe).
    pub fn new_offscreen() -> Result<Self, GfxError> {
        let entry = load_entry()?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"shapewright-xr")
            .api_version(VK_API_VERSION);
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        // SAFETY: `info` and what it points to live across the call.
        let instance = unsafe { entry.create_instance(&info, None) }
            .map_err(|r| GfxError::vk("vkCreateInstance", r))?;
        let guard = InstanceGuard(Some(instance));
        let instance = guard.get();
        // SAFETY: `instance` is a live instance.
        let pdevs = unsafe { instance.enumerate_physical_devices() }
            .map_err(|r| GfxError::vk("vkEnumeratePhysicalDevices", r))?;
        let rank = |t: vk::PhysicalDeviceType| match t {
            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            vk::PhysicalDeviceType::CPU => 3,
            _ => 4,
        };
        let mut best: Option<(u32, vk::PhysicalDevice, u32)> = None;
        for pdev in pdevs {
            // SAFETY: `pdev` was just enumerated from the live `instance`.
            let props = unsafe { instance.get_physical_device_properties(pdev) };
            if props.api_version < VK_API_VERSION {
                continue;
            }
            let Some(family) = graphics_queue_family(instance, pdev) else {
                continue;
            };
            let r = rank(props.device_type);
            if best.is_none_or(|(br, _, _)| r < br) {
                best = Some((r, pdev, family));
            }
        }
        let (_, pdev, family) = best.ok_or(GfxError::NoDevice)?;
        let device = with_device_info(family, |dinfo| {
            // SAFETY: `pdev` belongs to `instance`; `dinfo` and its chain
            // live across the call.
            unsafe { instance.create_device(pdev, dinfo, None) }
        })
        .map_err(|r| GfxError::vk("vkCreateDevice", r))?;
        let instance = guard.release();
        // SAFETY: `instance` and `device` were created above and are handed
        // over to the context, which destroys them exactly once.
        unsafe { Self::from_raw_parts(entry, instance, pdev, device, family) }
    }

    /// Adopts an instance and device created elsewhere (by OpenXR). The
    /// context destroys them on drop.
    ///
    /// # Safety
    /// `instance` and `device` must be live, `device` created from
    /// `physical_device` of `instance` with a queue in `queue_family` and
    /// the multiview feature enabled; nothing else may destroy them.
    pub unsafe fn from_raw_parts(
        entry: ash::Entry,
        instance: ash::Instance,
        physical_device: vk::PhysicalDevice,
        device: ash::Device,
        queue_family: u32,
    ) -> Result<Self, GfxError> {
        // SAFETY: the caller guarantees the handles are live and related.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: `device` is live; the pool is destroyed in Drop.
        let command_pool = match unsafe { device.create_command_pool(&pool_info, None) } {
            Ok(p) => p,
            Err(r) => {
                // SAFETY: we own both handles and nothing else uses them yet.
                unsafe {
                    device.destroy_device(None);
                    instance.destroy_instance(None);
                }
                return Err(GfxError::vk("vkCreateCommandPool", r));
            }
        };
        // SAFETY: `physical_device` belongs to the live `instance`.
        let memory_properties =
            unsafe { instance.get_physical_device_memory_properties(physical_device) };
        // SAFETY: as above.
        let props = unsafe { instance.get_physical_device_properties(physical_device) };
        let device_name = props
            .device_name_as_c_str()
            .map(|s: &CStr| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        Ok(Self {
            entry,
            instance,
            physical_device,
            device,
            queue,
            queue_family,
            command_pool,
            memory_properties,
            device_name,
        })
    }

    /// The Vulkan entry (loader) this context was made from.
    pub fn entry(&self) -> &ash::Entry {
        &self.entry
    }
    /// The Vulkan instance.
    pub fn instance(&self) -> &ash::Instance {
        &self.instance
    }
    /// The physical device.
    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.physical_device
    }
    /// The logical device.
    pub fn device(&self) -> &ash::Device {
        &self.device
    }
    /// The graphics queue.
    pub fn queue(&self) -> vk::Queue {
        self.queue
    }
    /// The graphics queue's family index.
    pub fn queue_family(&self) -> u32 {
        self.queue_family
    }
    /// The device's name as the driver reports it (e.g. `llvmpipe (...)`).
    pub fn device_name(&self) -> &str {
        &self.device_name
    }

    /// A memory type index allowed by `type_bits` with all of `flags`.
    pub fn memory_type(
        &self,
        type_bits: u32,
        flags: vk::MemoryPropertyFlags,
    ) -> Result<u32, GfxError> {
        let props = &self.memory_properties;
        (0..props.memory_type_count)
            .find(|&i| {
                type_bits & (1 << i) != 0
                    && props.memory_types[i as usize]
                        .property_flags
                        .contains(flags)
            })
            .ok_or(GfxError::NoMemoryType)
    }

    /// Memory for `req` of a type with all of `flags` (the caller binds it
    /// and frees it with the resource it backs).
    pub fn allocate(
        &self,
        req: vk::MemoryRequirements,
        flags: vk::MemoryPropertyFlags,
    ) -> Result<vk::DeviceMemory, GfxError> {
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(self.memory_type(req.memory_type_bits, flags)?);
        // SAFETY: live device, valid allocation info.
        unsafe { self.device.allocate_memory(&alloc, None) }
            .map_err(|r| GfxError::vk("vkAllocateMemory", r))
    }

    /// Records commands with `record` into a fresh primary command buffer,
    /// submits it and waits for it to finish.
    pub fn submit_and_wait(
        &self,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<(), GfxError> {
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device; the buffer is freed below.
        let cmd = unsafe { self.device.allocate_command_buffers(&alloc) }
            .map_err(|r| GfxError::vk("vkAllocateCommandBuffers", r))?[0];
        let result = (|| {
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            // SAFETY: `cmd` is a freshly allocated buffer in the initial state.
            unsafe { self.device.begin_command_buffer(cmd, &begin) }
                .map_err(|r| GfxError::vk("vkBeginCommandBuffer", r))?;
            record(&self.device, cmd);
            // SAFETY: `cmd` is in the recording state.
            unsafe { self.device.end_command_buffer(cmd) }
                .map_err(|r| GfxError::vk("vkEndCommandBuffer", r))?;
            // SAFETY: creating a fence on a live device; destroyed below.
            let fence = unsafe {
                self.device
                    .create_fence(&vk::FenceCreateInfo::default(), None)
            }
            .map_err(|r| GfxError::vk("vkCreateFence", r))?;
            let cmds = [cmd];
            let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
            // SAFETY: `cmd` is executable; queue and fence belong to this device;
            // we wait for the fence before touching anything the commands use.
            let r = unsafe {
                self.device
                    .queue_submit(self.queue, &submit, fence)
                    .and_then(|_| self.device.wait_for_fences(&[fence], true, u64::MAX))
            };
            // SAFETY: the fence is signalled or the submit failed; either way unused.
            unsafe { self.device.destroy_fence(fence, None) };
            r.map_err(|r| GfxError::vk("vkQueueSubmit/vkWaitForFences", r))
        })();
        // SAFETY: the buffer finished executing (or never ran).
        unsafe { self.device.free_command_buffers(self.command_pool, &[cmd]) };
        result
    }
}

impl Drop for GpuContext {
    fn drop(&mut self) {
        // SAFETY: every object made from this device holds an Arc to the
        // context, so they are gone by now; wait for the queue, then destroy
        // in reverse creation order, each exactly once.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.command_pool, None);
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

/// Destroys an instance on early return during construction.
struct InstanceGuard(Option<ash::Instance>);

impl InstanceGuard {
    fn get(&self) -> &ash::Instance {
        self.0
            .as_ref()
            .expect("guard holds the instance until released")
    }
    fn release(mut self) -> ash::Instance {
        self.0.take().expect("released once")
    }
}

impl Drop for InstanceGuard {
    fn drop(&mut self) {
        if let Some(i) = self.0.take() {
            // SAFETY: no device was created from it yet (or creation failed).
            unsafe { i.destroy_instance(None) };
        }
    }
}

/// The device both paths create (this module's, and the one OpenXR
/// creates for a headset session): one queue of the graphics `family`
/// and multiview, which [`GpuContext::from_raw_parts`] relies on. The
/// info and its chain live across `create`.
pub(crate) fn with_device_info<R>(
    family: u32,
    create: impl FnOnce(&vk::DeviceCreateInfo<'_>) -> R,
) -> R {
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&priorities)];
    let mut multiview = vk::PhysicalDeviceMultiviewFeatures::default().multiview(true);
    let dinfo = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .push_next(&mut multiview);
    create(&dinfo)
}
