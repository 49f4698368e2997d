//! XR_KHR_vulkan_enable2 and the graphics half of the core API: the
//! runtime creates the app's Vulkan instance/device through the app's
//! `vkGetInstanceProcAddr`, makes swapchain images on that device, paces
//! nothing (xrWaitFrame returns at once), validates submitted projection
//! layers and reports stereo views from the scripted head pose.

use ash::vk;
use ash::vk::Handle as _;
use openxr_sys as sys;
use sys::Handle as _;

use crate::api_instance::inst;
use crate::api_session::{sess, session_of};
use crate::api_spaces::{all_valid, tracked, untracked, world_pose};
use crate::script::{pose, FrameStats, Script};
use crate::state::{InstanceData, SessionData, SpaceKind, SwapchainData, VulkanState};
use crate::{done, input, output, with_rt};

const FORMATS: [vk::Format; 2] = [vk::Format::R8G8B8A8_SRGB, vk::Format::B8G8R8A8_SRGB];
const EYE_SIZE: u32 = 256;
const HALF_IPD: f32 = 0.032;
const HALF_FOV: f32 = std::f32::consts::FRAC_PI_4;

fn vulkan_enabled(i: &InstanceData) -> Result<(), sys::Result> {
    if i.extensions.iter().any(|e| e == "XR_KHR_vulkan_enable2") {
        Ok(())
    } else {
        Err(sys::Result::ERROR_FUNCTION_UNSUPPORTED)
    }
}

pub(crate) unsafe extern "system" fn get_vulkan_graphics_requirements2(
    instance: sys::Instance,
    system: sys::SystemId,
    reqs: *mut sys::GraphicsRequirementsVulkanKHR,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let reqs = match unsafe { output(reqs) } {
        Ok(r) => r,
        Err(e) => return e,
    };
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|i| {
            vulkan_enabled(i)?;
            if system.into_raw() != 1 {
                return Err(sys::Result::ERROR_SYSTEM_INVALID);
            }
            reqs.min_api_version_supported = sys::Version::new(1, 1, 0);
            reqs.max_api_version_supported = sys::Version::new(1, 3, 0);
            i.requirements_queried = true;
            Ok(sys::Result::SUCCESS)
        }))
    })
}

fn static_fn(
    gipa: Option<sys::platform::VkGetInstanceProcAddr>,
) -> Result<ash::StaticFn, sys::Result> {
    let gipa = gipa.ok_or(sys::Result::ERROR_VALIDATION_FAILURE)?;
    Ok(ash::StaticFn {
        // SAFETY: both are the C signature of vkGetInstanceProcAddr.
        get_instance_proc_addr: unsafe {
            std::mem::transmute::<sys::platform::VkGetInstanceProcAddr, vk::PFN_vkGetInstanceProcAddr>(
                gipa,
            )
        },
    })
}

pub(crate) unsafe extern "system" fn create_vulkan_instance(
    instance: sys::Instance,
    info: *const sys::VulkanInstanceCreateInfoKHR,
    vk_instance: *mut sys::platform::VkInstance,
    vk_result: *mut sys::platform::VkResult,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out, res) = match unsafe { (input(info), output(vk_instance), output(vk_result)) } {
        (Ok(i), Ok(o), Ok(r)) => (i, o, r),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|i| {
            vulkan_enabled(i)?;
            if info.ty != sys::VulkanInstanceCreateInfoKHR::TYPE
                || info.vulkan_create_info.is_null()
            {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if !i.requirements_queried {
                return Err(sys::Result::ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING);
            }
            let sf = static_fn(info.pfn_get_instance_proc_addr)?;
            // SAFETY: the app's loader entry point and create info, valid per
            // the extension's valid-usage rules.
            let entry = unsafe { ash::Entry::from_static_fn(sf.clone()) };
            // SAFETY: as above; the app owns (and destroys) the instance.
            let r = unsafe {
                entry.create_instance(
                    &*(info.vulkan_create_info as *const vk::InstanceCreateInfo),
                    None,
                )
            };
            match r {
                Ok(vi) => {
                    *out = vi.handle().as_raw() as _;
                    *res = vk::Result::SUCCESS.as_raw();
                    i.vulkan = Some(VulkanState {
                        instance: Some(vi),
                        physical_device: vk::PhysicalDevice::null(),
                        device: None,
                        queue_family: 0,
                        captured: false,
                    });
                }
                Err(e) => *res = e.as_raw(),
            }
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn get_vulkan_graphics_device2(
    instance: sys::Instance,
    info: *const sys::VulkanGraphicsDeviceGetInfoKHR,
    pdev: *mut sys::platform::VkPhysicalDevice,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(pdev)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|i| {
            vulkan_enabled(i)?;
            let v = i
                .vulkan
                .as_mut()
                .ok_or(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID)?;
            let vi = v
                .instance
                .as_ref()
                .ok_or(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID)?;
            if info.vulkan_instance as u64 != vi.handle().as_raw() {
                return Err(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID);
            }
            // SAFETY: the instance this runtime created for the app, still live.
            let devs = unsafe { vi.enumerate_physical_devices() }
                .map_err(|_| sys::Result::ERROR_RUNTIME_FAILURE)?;
            let d = *devs.first().ok_or(sys::Result::ERROR_RUNTIME_FAILURE)?;
            v.physical_device = d;
            *out = d.as_raw() as _;
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn create_vulkan_device(
    instance: sys::Instance,
    info: *const sys::VulkanDeviceCreateInfoKHR,
    vk_device: *mut sys::platform::VkDevice,
    vk_result: *mut sys::platform::VkResult,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out, res) = match unsafe { (input(info), output(vk_device), output(vk_result)) } {
        (Ok(i), Ok(o), Ok(r)) => (i, o, r),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|i| {
            vulkan_enabled(i)?;
            if info.ty != sys::VulkanDeviceCreateInfoKHR::TYPE || info.vulkan_create_info.is_null()
            {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let v = i
                .vulkan
                .as_mut()
                .ok_or(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID)?;
            if info.vulkan_physical_device as u64 != v.physical_device.as_raw() {
                return Err(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID);
            }
            let vi = v
                .instance
                .as_ref()
                .ok_or(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID)?;
            // SAFETY: physical device of the live instance; the app's create info.
            let r = unsafe {
                vi.create_device(
                    v.physical_device,
                    &*(info.vulkan_create_info as *const vk::DeviceCreateInfo),
                    None,
                )
            };
            match r {
                Ok(d) => {
                    *out = d.handle().as_raw() as _;
                    *res = vk::Result::SUCCESS.as_raw();
                    v.device = Some(d);
                }
                Err(e) => *res = e.as_raw(),
            }
            Ok(sys::Result::SUCCESS)
        }))
    })
}

/// Validates a session's Vulkan binding against what was created.
pub(crate) fn check_binding(
    i: &mut InstanceData,
    b: &sys::GraphicsBindingVulkanKHR,
) -> Result<(), sys::Result> {
    if b.ty != sys::GraphicsBindingVulkanKHR::TYPE {
        return Err(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID);
    }
    vulkan_enabled(i)?;
    if !i.requirements_queried {
        return Err(sys::Result::ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING);
    }
    let v = i
        .vulkan
        .as_ref()
        .ok_or(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID)?;
    let ok = v
        .instance
        .as_ref()
        .is_some_and(|x| x.handle().as_raw() == b.instance as u64)
        && v.physical_device.as_raw() == b.physical_device as u64
        && v.device
            .as_ref()
            .is_some_and(|d| d.handle().as_raw() == b.device as u64);
    if ok {
        if let Some(v) = i.vulkan.as_mut() {
            v.queue_family = b.queue_family_index;
        }
        Ok(())
    } else {
        Err(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID)
    }
}

/// Frees the images of `session`'s swapchains (children of the session).
pub(crate) fn destroy_swapchains(i: &mut InstanceData, session: u64) {
    let ids: Vec<u64> = i
        .swapchains
        .iter()
        .filter(|(_, s)| s.session == session)
        .map(|(k, _)| *k)
        .collect();
    for id in ids {
        if let Some(sc) = i.swapchains.remove(&id) {
            free_images(i, sc);
        }
    }
}

fn free_images(i: &InstanceData, sc: SwapchainData) {
    if let Some(d) = i.vulkan.as_ref().and_then(|v| v.device.as_ref()) {
        for (img, mem) in sc.images {
            // SAFETY: created by this runtime on the app's live device; the
            // app waited for its GPU work before destroying the swapchain.
            unsafe {
                d.destroy_image(img, None);
                d.free_memory(mem, None);
            }
        }
    }
}

/// Writes the frame statistics to the script's `stats_path`.
pub(crate) fn write_stats(script: &Script, s: &SessionData) {
    if let Some(p) = &script.stats_path {
        let stats = FrameStats {
            frames_ended: s.frame.ended,
            projection_layers: s.frame.projection_layers,
            graphics: s.graphics,
            haptics: s.haptics,
        };
        if let Ok(t) = serde_json::to_string(&stats) {
            let _ = std::fs::write(p, t);
        }
    }
}

/// Two-call idiom for plain values.
///
/// # Safety
/// `out` is null or holds `capacity` elements.
unsafe fn two_call<T: Copy>(
    items: &[T],
    capacity: u32,
    count: *mut u32,
    out: *mut T,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let Ok(count) = (unsafe { output(count) }) else {
        return sys::Result::ERROR_VALIDATION_FAILURE;
    };
    *count = items.len() as u32;
    if capacity == 0 {
        return sys::Result::SUCCESS;
    }
    if (capacity as usize) < items.len() {
        return sys::Result::ERROR_SIZE_INSUFFICIENT;
    }
    if out.is_null() {
        return sys::Result::ERROR_VALIDATION_FAILURE;
    }
    for (k, it) in items.iter().enumerate() {
        // SAFETY: `out` holds `capacity` >= items.len() elements.
        unsafe { *out.add(k) = *it };
    }
    sys::Result::SUCCESS
}

pub(crate) unsafe extern "system" fn enumerate_view_configurations(
    instance: sys::Instance,
    system: sys::SystemId,
    capacity: u32,
    count: *mut u32,
    out: *mut sys::ViewConfigurationType,
) -> sys::Result {
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|_| {
            if system.into_raw() != 1 {
                return Err(sys::Result::ERROR_SYSTEM_INVALID);
            }
            // SAFETY: forwarded caller pointers.
            Ok(unsafe {
                two_call(
                    &[sys::ViewConfigurationType::PRIMARY_STEREO],
                    capacity,
                    count,
                    out,
                )
            })
        }))
    })
}

pub(crate) unsafe extern "system" fn enumerate_view_configuration_views(
    instance: sys::Instance,
    system: sys::SystemId,
    ty: sys::ViewConfigurationType,
    capacity: u32,
    count: *mut u32,
    out: *mut sys::ViewConfigurationView,
) -> sys::Result {
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|_| {
            if system.into_raw() != 1 {
                return Err(sys::Result::ERROR_SYSTEM_INVALID);
            }
            if ty != sys::ViewConfigurationType::PRIMARY_STEREO {
                return Err(sys::Result::ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
            }
            let v = sys::ViewConfigurationView {
                ty: sys::ViewConfigurationView::TYPE,
                next: std::ptr::null_mut(),
                recommended_image_rect_width: EYE_SIZE,
                max_image_rect_width: 4 * EYE_SIZE,
                recommended_image_rect_height: EYE_SIZE,
                max_image_rect_height: 4 * EYE_SIZE,
                recommended_swapchain_sample_count: 1,
                max_swapchain_sample_count: 1,
            };
            // SAFETY: forwarded caller pointers.
            Ok(unsafe { two_call(&[v, v], capacity, count, out) })
        }))
    })
}

pub(crate) unsafe extern "system" fn enumerate_environment_blend_modes(
    instance: sys::Instance,
    system: sys::SystemId,
    ty: sys::ViewConfigurationType,
    capacity: u32,
    count: *mut u32,
    out: *mut sys::EnvironmentBlendMode,
) -> sys::Result {
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|_| {
            if system.into_raw() != 1 {
                return Err(sys::Result::ERROR_SYSTEM_INVALID);
            }
            if ty != sys::ViewConfigurationType::PRIMARY_STEREO {
                return Err(sys::Result::ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
            }
            // SAFETY: forwarded caller pointers.
            Ok(unsafe { two_call(&[sys::EnvironmentBlendMode::OPAQUE], capacity, count, out) })
        }))
    })
}

pub(crate) unsafe extern "system" fn enumerate_swapchain_formats(
    session: sys::Session,
    capacity: u32,
    count: *mut u32,
    out: *mut i64,
) -> sys::Result {
    with_rt(|rt| {
        done(sess(rt, session).map(|i| {
            // Headless sessions enumerate no formats (XR_MND_headless).
            let formats: Vec<i64> = if session_of(i).graphics {
                FORMATS.iter().map(|f| i64::from(f.as_raw())).collect()
            } else {
                Vec::new()
            };
            // SAFETY: forwarded caller pointers.
            unsafe { two_call(&formats, capacity, count, out) }
        }))
    })
}

pub(crate) unsafe extern "system" fn create_swapchain(
    session: sys::Session,
    info: *const sys::SwapchainCreateInfo,
    swapchain: *mut sys::Swapchain,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(swapchain)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let h = rt.handle();
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::SwapchainCreateInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let format = vk::Format::from_raw(info.format as i32);
            if !session_of(i).graphics || !FORMATS.contains(&format) {
                return Err(sys::Result::ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED);
            }
            if info.sample_count != 1 || info.face_count != 1 || info.mip_count != 1 {
                return Err(sys::Result::ERROR_FEATURE_UNSUPPORTED);
            }
            if info.width == 0
                || info.height == 0
                || info.width > 4 * EYE_SIZE
                || info.height > 4 * EYE_SIZE
                || info.array_size == 0
                || info.array_size > 2
            {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let v = i
                .vulkan
                .as_ref()
                .ok_or(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID)?;
            let (Some(vi), Some(d)) = (v.instance.as_ref(), v.device.as_ref()) else {
                return Err(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID);
            };
            // SAFETY: the app's live instance and physical device.
            let mem_props = unsafe { vi.get_physical_device_memory_properties(v.physical_device) };
            let mut images = Vec::new();
            for _ in 0..3 {
                let ci = vk::ImageCreateInfo::default()
                    .image_type(vk::ImageType::TYPE_2D)
                    .format(format)
                    .extent(vk::Extent3D {
                        width: info.width,
                        height: info.height,
                        depth: 1,
                    })
                    .mip_levels(1)
                    .array_layers(info.array_size)
                    .samples(vk::SampleCountFlags::TYPE_1)
                    .tiling(vk::ImageTiling::OPTIMAL)
                    .usage(
                        vk::ImageUsageFlags::COLOR_ATTACHMENT
                            | vk::ImageUsageFlags::SAMPLED
                            | vk::ImageUsageFlags::TRANSFER_SRC,
                    )
                    .initial_layout(vk::ImageLayout::UNDEFINED);
                // SAFETY: the app's live device; freed in free_images.
                let made = unsafe {
                    d.create_image(&ci, None).and_then(|img| {
                        let req = d.get_image_memory_requirements(img);
                        let t = (0..mem_props.memory_type_count)
                            .find(|&t| req.memory_type_bits & (1 << t) != 0)
                            .unwrap_or(0);
                        let mem = d.allocate_memory(
                            &vk::MemoryAllocateInfo::default()
                                .allocation_size(req.size)
                                .memory_type_index(t),
                            None,
                        );
                        match mem {
                            Ok(m) => d.bind_image_memory(img, m, 0).map(|_| (img, m)),
                            Err(e) => {
                                d.destroy_image(img, None);
                                Err(e)
                            }
                        }
                    })
                };
                match made {
                    Ok(x) => images.push(x),
                    Err(_) => {
                        let sc = SwapchainData {
                            session: session.into_raw(),
                            images,
                            array_size: 0,
                            width: 0,
                            height: 0,
                            next: 0,
                            acquired: Default::default(),
                            released_once: false,
                            last_released: 0,
                            format,
                        };
                        free_images(i, sc);
                        return Err(sys::Result::ERROR_OUT_OF_MEMORY);
                    }
                }
            }
            i.swapchains.insert(
                h,
                SwapchainData {
                    session: session.into_raw(),
                    images,
                    array_size: info.array_size,
                    width: info.width,
                    height: info.height,
                    next: 0,
                    acquired: Default::default(),
                    released_once: false,
                    last_released: 0,
                    format,
                },
            );
            *out = sys::Swapchain::from_raw(h);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn destroy_swapchain(swapchain: sys::Swapchain) -> sys::Result {
    with_rt(|rt| {
        let Some(i) = rt.instance.as_mut() else {
            return sys::Result::ERROR_HANDLE_INVALID;
        };
        match i.swapchains.remove(&swapchain.into_raw()) {
            Some(sc) => {
                free_images(i, sc);
                sys::Result::SUCCESS
            }
            None => sys::Result::ERROR_HANDLE_INVALID,
        }
    })
}

fn swapchain_mut(
    rt: &mut crate::state::Runtime,
    h: sys::Swapchain,
) -> Result<&mut SwapchainData, sys::Result> {
    let session = rt
        .instance
        .as_ref()
        .and_then(|i| i.swapchains.get(&h.into_raw()))
        .map(|s| s.session)
        .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
    let i = sess(rt, sys::Session::from_raw(session))?;
    i.swapchains
        .get_mut(&h.into_raw())
        .ok_or(sys::Result::ERROR_HANDLE_INVALID)
}

pub(crate) unsafe extern "system" fn enumerate_swapchain_images(
    swapchain: sys::Swapchain,
    capacity: u32,
    count: *mut u32,
    out: *mut sys::SwapchainImageBaseHeader,
) -> sys::Result {
    with_rt(|rt| {
        done(swapchain_mut(rt, swapchain).map(|sc| {
            let imgs: Vec<sys::SwapchainImageVulkanKHR> = sc
                .images
                .iter()
                .map(|(img, _)| sys::SwapchainImageVulkanKHR {
                    ty: sys::SwapchainImageVulkanKHR::TYPE,
                    next: std::ptr::null_mut(),
                    image: img.as_raw(),
                })
                .collect();
            // SAFETY: for a Vulkan session the app passes an array of
            // XrSwapchainImageVulkanKHR (the base header is its prefix).
            unsafe {
                two_call(
                    &imgs,
                    capacity,
                    count,
                    out.cast::<sys::SwapchainImageVulkanKHR>(),
                )
            }
        }))
    })
}

pub(crate) unsafe extern "system" fn acquire_swapchain_image(
    swapchain: sys::Swapchain,
    _info: *const sys::SwapchainImageAcquireInfo,
    index: *mut u32,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let index = match unsafe { output(index) } {
        Ok(x) => x,
        Err(e) => return e,
    };
    with_rt(|rt| {
        done(swapchain_mut(rt, swapchain).and_then(|sc| {
            if sc.acquired.len() >= sc.images.len() {
                return Err(sys::Result::ERROR_CALL_ORDER_INVALID);
            }
            let k = sc.next;
            sc.next = (sc.next + 1) % sc.images.len();
            sc.acquired.push_back((k, false));
            *index = k as u32;
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn wait_swapchain_image(
    swapchain: sys::Swapchain,
    info: *const sys::SwapchainImageWaitInfo,
) -> sys::Result {
    if info.is_null() {
        return sys::Result::ERROR_VALIDATION_FAILURE;
    }
    with_rt(|rt| {
        done(swapchain_mut(rt, swapchain).and_then(
            |sc| match sc.acquired.iter_mut().find(|a| !a.1) {
                Some(a) => {
                    a.1 = true;
                    Ok(sys::Result::SUCCESS)
                }
                None => Err(sys::Result::ERROR_CALL_ORDER_INVALID),
            },
        ))
    })
}

pub(crate) unsafe extern "system" fn release_swapchain_image(
    swapchain: sys::Swapchain,
    _info: *const sys::SwapchainImageReleaseInfo,
) -> sys::Result {
    with_rt(|rt| {
        done(
            swapchain_mut(rt, swapchain).and_then(|sc| match sc.acquired.front() {
                Some((_, true)) => {
                    sc.acquired.pop_front();
                    sc.released_once = true;
                    Ok(sys::Result::SUCCESS)
                }
                _ => Err(sys::Result::ERROR_CALL_ORDER_INVALID),
            }),
        )
    })
}

fn renders(state: sys::SessionState) -> bool {
    state == sys::SessionState::VISIBLE || state == sys::SessionState::FOCUSED
}

pub(crate) unsafe extern "system" fn wait_frame(
    session: sys::Session,
    _info: *const sys::FrameWaitInfo,
    state: *mut sys::FrameState,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let state = match unsafe { output(state) } {
        Ok(s) => s,
        Err(e) => return e,
    };
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            let s = session_of(i);
            if !s.running {
                return Err(sys::Result::ERROR_SESSION_NOT_RUNNING);
            }
            s.frame.waited = true;
            let period = 11_111_111;
            state.predicted_display_period = sys::Duration::from_nanos(period);
            state.predicted_display_time =
                sys::Time::from_nanos(crate::api_session::now().as_nanos() + period);
            state.should_render = renders(s.state).into();
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn begin_frame(
    session: sys::Session,
    _info: *const sys::FrameBeginInfo,
) -> sys::Result {
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            let s = session_of(i);
            if !s.running {
                return Err(sys::Result::ERROR_SESSION_NOT_RUNNING);
            }
            if !s.frame.waited {
                return Err(sys::Result::ERROR_CALL_ORDER_INVALID);
            }
            s.frame.waited = false;
            if s.frame.begun {
                return Ok(sys::Result::FRAME_DISCARDED);
            }
            s.frame.begun = true;
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn end_frame(
    session: sys::Session,
    info: *const sys::FrameEndInfo,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let info = match unsafe { input(info) } {
        Ok(i) => i,
        Err(e) => return e,
    };
    let mut layers = Vec::new();
    for k in 0..info.layer_count as usize {
        if info.layers.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: `layers` holds layer_count pointers to layer structs.
        let l = unsafe { *info.layers.add(k) };
        if l.is_null() {
            return sys::Result::ERROR_LAYER_INVALID;
        }
        // SAFETY: every layer starts with the base header.
        if unsafe { (*l).ty } != sys::CompositionLayerProjection::TYPE {
            return sys::Result::ERROR_LAYER_INVALID;
        }
        // SAFETY: its type says it is a projection layer.
        let p = unsafe { &*(l as *const sys::CompositionLayerProjection) };
        if p.view_count != 2 || p.views.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: `views` holds view_count (2) projection views.
        let views = unsafe { [*p.views, *p.views.add(1)] };
        layers.push((p.space.into_raw(), views));
    }
    with_rt(|rt| {
        let capture_path = rt.script.capture_path.clone();
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::FrameEndInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if !session_of(i).frame.begun {
                return Err(sys::Result::ERROR_CALL_ORDER_INVALID);
            }
            if info.display_time.as_nanos() <= 0 {
                return Err(sys::Result::ERROR_TIME_INVALID);
            }
            if info.environment_blend_mode != sys::EnvironmentBlendMode::OPAQUE {
                return Err(sys::Result::ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED);
            }
            for (space, views) in &layers {
                if !i.spaces.contains_key(space) {
                    return Err(sys::Result::ERROR_HANDLE_INVALID);
                }
                for v in views {
                    let sc = i
                        .swapchains
                        .get(&v.sub_image.swapchain.into_raw())
                        .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
                    if !sc.released_once {
                        return Err(sys::Result::ERROR_LAYER_INVALID);
                    }
                    if v.sub_image.image_array_index >= sc.array_size {
                        return Err(sys::Result::ERROR_VALIDATION_FAILURE);
                    }
                    let r = v.sub_image.image_rect;
                    if r.offset.x < 0
                        || r.offset.y < 0
                        || r.extent.width <= 0
                        || r.extent.height <= 0
                        || (r.offset.x + r.extent.width) as u32 > sc.width
                        || (r.offset.y + r.extent.height) as u32 > sc.height
                    {
                        return Err(sys::Result::ERROR_SWAPCHAIN_RECT_INVALID);
                    }
                    let q = v.pose.orientation;
                    let n = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
                    if !(n - 1.0).abs().lt(&0.01) {
                        return Err(sys::Result::ERROR_POSE_INVALID);
                    }
                }
            }
            if let (Some(path), Some((_, views))) = (capture_path.as_ref(), layers.first()) {
                capture(i, &views[0], path);
            }
            let n = layers.len() as u64;
            let s = session_of(i);
            s.frame.begun = false;
            s.frame.ended += 1;
            s.frame.projection_layers += n;
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn locate_views(
    session: sys::Session,
    info: *const sys::ViewLocateInfo,
    state: *mut sys::ViewState,
    capacity: u32,
    count: *mut u32,
    views: *mut sys::View,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, state) = match unsafe { (input(info), output(state)) } {
        (Ok(i), Ok(s)) => (i, s),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let profile = rt.script.profile.clone();
        let current = rt.script.live(rt.step);
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::ViewLocateInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if info.view_configuration_type != sys::ViewConfigurationType::PRIMARY_STEREO {
                return Err(sys::Result::ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
            }
            if info.display_time.as_nanos() <= 0 {
                return Err(sys::Result::ERROR_TIME_INVALID);
            }
            let base = *i
                .spaces
                .get(&info.space.into_raw())
                .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
            let frame = session_of(i).synced.clone().unwrap_or(current);
            crate::api_spaces::settle_local_origin(i, &frame);
            let head = crate::state::SpaceInfo {
                session: session.into_raw(),
                kind: SpaceKind::Reference(sys::ReferenceSpaceType::VIEW),
                offset: ([0.0; 3], [0.0, 0.0, 0.0, 1.0]),
            };
            let located = match (
                world_pose(i, &profile, &frame, &head),
                world_pose(i, &profile, &frame, &base),
            ) {
                (Some((h, nh)), Some((b, nb))) => {
                    Some((pose::compose(pose::inverse(b), h), nh || nb))
                }
                _ => None,
            };
            let fov = sys::Fovf {
                angle_left: -HALF_FOV,
                angle_right: HALF_FOV,
                angle_up: HALF_FOV,
                angle_down: -HALF_FOV,
            };
            let out: Vec<sys::View> = [-HALF_IPD, HALF_IPD]
                .iter()
                .map(|dx| sys::View {
                    ty: sys::View::TYPE,
                    next: std::ptr::null_mut(),
                    pose: match located {
                        Some((h, nan)) => tracked(
                            pose::compose(h, ([*dx, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0])),
                            nan,
                        ),
                        None => untracked(),
                    },
                    fov,
                })
                .collect();
            state.view_state_flags = if located.is_some() {
                let f = all_valid();
                sys::ViewStateFlags::from_raw(f.into_raw())
            } else {
                sys::ViewStateFlags::EMPTY
            };
            // SAFETY: forwarded caller pointers.
            Ok(unsafe { two_call(&out, capacity, count, views) })
        }))
    })
}

/// Copies the layer a projection view shows (its swapchain's last released
/// image, its array index) into a file: 8-byte header (width, height as
/// little-endian u32) then RGBA8 rows. Once per process; failures are
/// reported on stderr and leave no file.
fn capture(i: &mut InstanceData, view: &sys::CompositionLayerProjectionView, path: &str) {
    let Some(v) = i.vulkan.as_ref() else { return };
    if v.captured {
        return;
    }
    let (Some(vi), Some(d)) = (v.instance.as_ref(), v.device.as_ref()) else {
        return;
    };
    let Some(sc) = i.swapchains.get(&view.sub_image.swapchain.into_raw()) else {
        return;
    };
    let Some(&(image, _)) = sc.images.get(sc.last_released) else {
        return;
    };
    let (w, h, layer) = (sc.width, sc.height, view.sub_image.image_array_index);
    let bgra = sc.format == vk::Format::B8G8R8A8_SRGB;
    let size = u64::from(w) * u64::from(h) * 4;
    // SAFETY: every handle is live on the app's device; the app released
    // the image (its rendering was waited for), the runtime owns the copy's
    // resources and waits for the queue before freeing them.
    let r = unsafe {
        (|| -> Result<Vec<u8>, vk::Result> {
            let queue = d.get_device_queue(v.queue_family, 0);
            let pool = d.create_command_pool(
                &vk::CommandPoolCreateInfo::default().queue_family_index(v.queue_family),
                None,
            )?;
            let buf = d.create_buffer(
                &vk::BufferCreateInfo::default()
                    .size(size)
                    .usage(vk::BufferUsageFlags::TRANSFER_DST),
                None,
            )?;
            let req = d.get_buffer_memory_requirements(buf);
            let props = vi.get_physical_device_memory_properties(v.physical_device);
            let want =
                vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
            let t = (0..props.memory_type_count)
                .find(|&t| {
                    req.memory_type_bits & (1 << t) != 0
                        && props.memory_types[t as usize].property_flags.contains(want)
                })
                .ok_or(vk::Result::ERROR_FEATURE_NOT_PRESENT)?;
            let mem = d.allocate_memory(
                &vk::MemoryAllocateInfo::default()
                    .allocation_size(req.size)
                    .memory_type_index(t),
                None,
            )?;
            d.bind_buffer_memory(buf, mem, 0)?;
            let cmd = d.allocate_command_buffers(
                &vk::CommandBufferAllocateInfo::default()
                    .command_pool(pool)
                    .level(vk::CommandBufferLevel::PRIMARY)
                    .command_buffer_count(1),
            )?[0];
            d.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
            let range = vk::ImageSubresourceRange {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                base_mip_level: 0,
                level_count: 1,
                base_array_layer: 0,
                layer_count: sc.array_size,
            };
            let to_src = vk::ImageMemoryBarrier::default()
                .image(image)
                .old_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
                .dst_access_mask(vk::AccessFlags::TRANSFER_READ)
                .subresource_range(range);
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[to_src],
            );
            let region = vk::BufferImageCopy {
                image_subresource: vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: layer,
                    layer_count: 1,
                },
                image_extent: vk::Extent3D {
                    width: w,
                    height: h,
                    depth: 1,
                },
                ..Default::default()
            };
            d.cmd_copy_image_to_buffer(
                cmd,
                image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buf,
                &[region],
            );
            let back = vk::ImageMemoryBarrier::default()
                .image(image)
                .old_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                .new_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .src_access_mask(vk::AccessFlags::TRANSFER_READ)
                .subresource_range(range);
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[back],
            );
            d.end_command_buffer(cmd)?;
            let cmds = [cmd];
            d.queue_submit(
                queue,
                &[vk::SubmitInfo::default().command_buffers(&cmds)],
                vk::Fence::null(),
            )?;
            d.queue_wait_idle(queue)?;
            let p = d.map_memory(mem, 0, size, vk::MemoryMapFlags::empty())?;
            let bytes = std::slice::from_raw_parts(p as *const u8, size as usize).to_vec();
            d.unmap_memory(mem);
            d.destroy_command_pool(pool, None);
            d.destroy_buffer(buf, None);
            d.free_memory(mem, None);
            Ok(bytes)
        })()
    };
    match r {
        Ok(mut bytes) => {
            if bgra {
                bytes.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
            }
            let mut out = Vec::with_capacity(bytes.len() + 8);
            out.extend_from_slice(&w.to_le_bytes());
            out.extend_from_slice(&h.to_le_bytes());
            out.extend_from_slice(&bytes);
            if let Err(e) = std::fs::write(path, out) {
                eprintln!("shapewright-xr-testrt: writing {path}: {e}");
            }
        }
        Err(e) => eprintln!("shapewright-xr-testrt: capture failed: {e}"),
    }
    if let Some(v) = i.vulkan.as_mut() {
        v.captured = true;
    }
}
