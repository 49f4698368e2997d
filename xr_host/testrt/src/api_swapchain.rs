//! Swapchains and view configurations: the runtime makes swapchain images
//! on the app's Vulkan device and hands them out in turn.

use ash::vk;
use ash::vk::Handle as _;
use openxr_sys as sys;
use sys::Handle as _;

use crate::api_instance::{check_stereo, check_system, inst};
use crate::api_session::{sess, session_of};
use crate::state::{InstanceData, SwapchainData};
use crate::{done, input, output, with_rt};

const FORMATS: [vk::Format; 2] = [vk::Format::R8G8B8A8_SRGB, vk::Format::B8G8R8A8_SRGB];
const EYE_SIZE: u32 = 256;

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

/// Two-call idiom for plain values.
///
/// # Safety
/// `out` is null or holds `capacity` elements.
pub(crate) unsafe fn two_call<T: Copy>(
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
            check_system(system)?;
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
            check_system(system)?;
            check_stereo(ty)?;
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
            check_system(system)?;
            check_stereo(ty)?;
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
