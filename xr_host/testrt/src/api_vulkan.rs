//! XR_KHR_vulkan_enable2: the runtime creates the app's Vulkan
//! instance/device through the app's `vkGetInstanceProcAddr` and checks a
//! session's binding against them. Swapchains are in `api_swapchain`,
//! the frame loop and views in `api_frame`.

use ash::vk;
use ash::vk::Handle as _;
use openxr_sys as sys;

use crate::api_instance::{check_system, inst};
use crate::state::{InstanceData, VulkanState};
use crate::{done, input, output, with_rt};

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
            check_system(system)?;
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
