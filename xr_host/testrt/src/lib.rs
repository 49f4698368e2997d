//! A scripted OpenXR runtime for the host's integration tests, in the
//! spirit of Unity's OpenXR MockRuntime. The real loader finds it through
//! a runtime manifest named by `XR_RUNTIME_JSON`; it exports
//! `xrNegotiateLoaderRuntimeInterface` and implements only the functions
//! the host calls, with the spec's return codes (`xrGetInstanceProcAddr`
//! answers XR_ERROR_FUNCTION_UNSUPPORTED for the rest).
//!
//! It offers XR_MND_headless, XR_KHR_convert_timespec_time and (if the
//! script says so) XR_EXT_hand_tracking and XR_KHR_vulkan_enable2 (it then
//! creates the app's Vulkan instance and device, makes swapchain images on
//! that device, and validates submitted stereo projection layers). Poses, buttons and joints come
//! from the script ([`script::Script`], path in
//! `SHAPEWRIGHT_TESTRT_SCRIPT`), which can also inject tracking loss, NaN
//! poses, LOSS_PENDING and instance loss.

#![allow(clippy::missing_safety_doc)]

mod api_actions;
mod api_frame;
mod api_hands;
mod api_instance;
mod api_session;
mod api_spaces;
mod api_swapchain;
mod api_vulkan;
pub mod script;
mod state;

use std::ffi::{c_char, CStr};
use std::sync::Mutex;

use openxr_sys as sys;
use sys::Handle as _;

use state::Runtime;

static RUNTIME: Mutex<Runtime> = Mutex::new(Runtime::new());

/// The runtime's name as xrGetInstanceProperties reports it.
pub const RUNTIME_NAME: &str = "Shapewright test runtime";

/// Runs `f` on the runtime state, mapping a poisoned lock or a panic to
/// XR_ERROR_RUNTIME_FAILURE (a panic must not unwind into the loader).
pub(crate) fn with_rt(f: impl FnOnce(&mut Runtime) -> sys::Result) -> sys::Result {
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match RUNTIME.lock() {
        Ok(mut g) => f(&mut g),
        Err(_) => sys::Result::ERROR_RUNTIME_FAILURE,
    }));
    r.unwrap_or(sys::Result::ERROR_RUNTIME_FAILURE)
}

/// Borrows an input struct; null is XR_ERROR_VALIDATION_FAILURE.
///
/// # Safety
/// `p` is null or points to a valid `T` for the duration of the call (the
/// caller's obligation under the spec's valid-usage rules).
pub(crate) unsafe fn input<'a, T>(p: *const T) -> Result<&'a T, sys::Result> {
    // SAFETY: null handled by as_ref; otherwise valid per the caller.
    unsafe { p.as_ref() }.ok_or(sys::Result::ERROR_VALIDATION_FAILURE)
}

/// Borrows an output struct; null is XR_ERROR_VALIDATION_FAILURE.
///
/// # Safety
/// `p` is null or points to a writable `T` for the duration of the call.
pub(crate) unsafe fn output<'a, T>(p: *mut T) -> Result<&'a mut T, sys::Result> {
    // SAFETY: null handled by as_mut; otherwise valid per the caller.
    unsafe { p.as_mut() }.ok_or(sys::Result::ERROR_VALIDATION_FAILURE)
}

/// Reads a NUL-terminated string.
///
/// # Safety
/// `p` is null or a valid NUL-terminated string.
pub(crate) unsafe fn cstr(p: *const c_char) -> Result<String, sys::Result> {
    if p.is_null() {
        return Err(sys::Result::ERROR_VALIDATION_FAILURE);
    }
    // SAFETY: non-null and NUL-terminated per the caller.
    Ok(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

/// Reads a fixed-size, NUL-terminated char array.
pub(crate) fn fixed_str(a: &[c_char]) -> Option<String> {
    let end = a.iter().position(|&c| c == 0)?;
    Some(a[..end].iter().map(|&c| c as u8 as char).collect())
}

/// Writes `s` NUL-terminated into a fixed array (truncating).
pub(crate) fn write_fixed(dst: &mut [c_char], s: &str) {
    let n = s.len().min(dst.len().saturating_sub(1));
    for (d, b) in dst.iter_mut().zip(s.bytes().take(n)) {
        *d = b as c_char;
    }
    if let Some(d) = dst.get_mut(n) {
        *d = 0;
    }
}

/// Collapses `Result<(), sys::Result>` into an XrResult.
pub(crate) fn done(r: Result<sys::Result, sys::Result>) -> sys::Result {
    r.unwrap_or_else(|e| e)
}

/// The loader's entry point (OpenXR loader interface, §"Runtime interface
/// negotiation").
///
/// # Safety
/// Called by the loader with valid pointers.
#[no_mangle]
pub unsafe extern "system" fn xrNegotiateLoaderRuntimeInterface(
    loader_info: *const sys::NegotiateLoaderInfo,
    request: *mut sys::NegotiateRuntimeRequest,
) -> sys::Result {
    // SAFETY: pointers from the loader, null-checked by the helpers.
    let (info, req) = match unsafe { (input(loader_info), output(request)) } {
        (Ok(i), Ok(r)) => (i, r),
        _ => return sys::Result::ERROR_INITIALIZATION_FAILED,
    };
    if info.struct_type != sys::LoaderInterfaceStructs::LOADER_INFO
        || info.struct_version != sys::LOADER_INFO_STRUCT_VERSION as u32
        || info.struct_size != std::mem::size_of::<sys::NegotiateLoaderInfo>()
        || req.struct_type != sys::LoaderInterfaceStructs::RUNTIME_REQUEST
        || req.struct_version != sys::RUNTIME_INFO_STRUCT_VERSION as u32
        || req.struct_size != std::mem::size_of::<sys::NegotiateRuntimeRequest>()
    {
        return sys::Result::ERROR_INITIALIZATION_FAILED;
    }
    let iface = sys::CURRENT_LOADER_RUNTIME_VERSION as u32;
    if info.min_interface_version > iface || info.max_interface_version < iface {
        return sys::Result::ERROR_INITIALIZATION_FAILED;
    }
    let api = sys::Version::new(1, 0, 34);
    if info.min_api_version.major() > 1 || info.max_api_version.major() < 1 {
        return sys::Result::ERROR_INITIALIZATION_FAILED;
    }
    req.runtime_interface_version = iface;
    req.runtime_api_version = api;
    req.get_instance_proc_addr = Some(xr_get_instance_proc_addr);
    sys::Result::SUCCESS
}

macro_rules! table {
    ($name:expr; $($s:literal => $f:path,)*) => {
        match $name {
            $($s => Some(
                // SAFETY: the loader casts the pointer back to this
                // function's own PFN type before calling it.
                unsafe { std::mem::transmute::<*const (), sys::pfn::VoidFunction>($f as *const ()) }
            ),)*
            _ => None,
        }
    };
}

fn lookup(name: &str, exts: &[String]) -> Option<sys::pfn::VoidFunction> {
    use api_actions as a;
    use api_frame as f;
    use api_hands as h;
    use api_instance as i;
    use api_session as s;
    use api_spaces as sp;
    use api_swapchain as sc;
    use api_vulkan as v;
    let ext = |e: &str| exts.iter().any(|x| x == e);
    if name.contains("Timespec") && !ext("XR_KHR_convert_timespec_time") {
        return None;
    }
    if name.contains("Vulkan") && !ext("XR_KHR_vulkan_enable2") {
        return None;
    }
    if name.ends_with("EXT") && !ext("XR_EXT_hand_tracking") {
        return None;
    }
    if NOT_CALLED_BY_HOST.contains(&name) {
        // SAFETY: the loader casts this back to the named function's PFN
        // type; `not_called_by_host` takes no arguments and returns an
        // XrResult, and under the C calling convention a callee that
        // ignores its arguments is called correctly with any of them.
        return Some(unsafe {
            std::mem::transmute::<*const (), sys::pfn::VoidFunction>(
                not_called_by_host as *const (),
            )
        });
    }
    table!(name;
        "xrGetInstanceProcAddr" => xr_get_instance_proc_addr,
        "xrEnumerateInstanceExtensionProperties" => i::enumerate_instance_extension_properties,
        "xrEnumerateApiLayerProperties" => i::enumerate_api_layer_properties,
        "xrCreateInstance" => i::create_instance,
        "xrDestroyInstance" => i::destroy_instance,
        "xrGetInstanceProperties" => i::get_instance_properties,
        "xrResultToString" => i::result_to_string,
        "xrGetSystem" => i::get_system,
        "xrGetSystemProperties" => i::get_system_properties,
        "xrStringToPath" => i::string_to_path,
        "xrPathToString" => i::path_to_string,
        "xrCreateActionSet" => i::create_action_set,
        "xrDestroyActionSet" => i::destroy_action_set,
        "xrCreateAction" => i::create_action,
        "xrDestroyAction" => i::destroy_action,
        "xrSuggestInteractionProfileBindings" => i::suggest_interaction_profile_bindings,
        "xrConvertTimespecTimeToTimeKHR" => i::convert_timespec_time_to_time,
        "xrConvertTimeToTimespecTimeKHR" => i::convert_time_to_timespec_time,
        "xrPollEvent" => s::poll_event,
        "xrCreateSession" => s::create_session,
        "xrDestroySession" => s::destroy_session,
        "xrBeginSession" => s::begin_session,
        "xrEndSession" => s::end_session,
        "xrRequestExitSession" => s::request_exit_session,
        "xrAttachSessionActionSets" => a::attach_session_action_sets,
        "xrSyncActions" => a::sync_actions,
        "xrGetActionStateBoolean" => a::get_action_state_boolean,
        "xrGetActionStateFloat" => a::get_action_state_float,
        "xrGetActionStatePose" => a::get_action_state_pose,
        "xrEnumerateReferenceSpaces" => sp::enumerate_reference_spaces,
        "xrCreateReferenceSpace" => sp::create_reference_space,
        "xrCreateActionSpace" => sp::create_action_space,
        "xrDestroySpace" => sp::destroy_space,
        "xrLocateSpace" => sp::locate_space,
        "xrCreateHandTrackerEXT" => h::create_hand_tracker,
        "xrDestroyHandTrackerEXT" => h::destroy_hand_tracker,
        "xrLocateHandJointsEXT" => h::locate_hand_joints,
        "xrGetVulkanGraphicsRequirements2KHR" => v::get_vulkan_graphics_requirements2,
        "xrCreateVulkanInstanceKHR" => v::create_vulkan_instance,
        "xrGetVulkanGraphicsDevice2KHR" => v::get_vulkan_graphics_device2,
        "xrCreateVulkanDeviceKHR" => v::create_vulkan_device,
        "xrEnumerateViewConfigurations" => sc::enumerate_view_configurations,
        "xrEnumerateViewConfigurationViews" => sc::enumerate_view_configuration_views,
        "xrEnumerateEnvironmentBlendModes" => sc::enumerate_environment_blend_modes,
        "xrEnumerateSwapchainFormats" => sc::enumerate_swapchain_formats,
        "xrCreateSwapchain" => sc::create_swapchain,
        "xrDestroySwapchain" => sc::destroy_swapchain,
        "xrEnumerateSwapchainImages" => sc::enumerate_swapchain_images,
        "xrAcquireSwapchainImage" => sc::acquire_swapchain_image,
        "xrWaitSwapchainImage" => sc::wait_swapchain_image,
        "xrReleaseSwapchainImage" => sc::release_swapchain_image,
        "xrWaitFrame" => f::wait_frame,
        "xrBeginFrame" => f::begin_frame,
        "xrEndFrame" => f::end_frame,
        "xrLocateViews" => f::locate_views,
        "xrGetCurrentInteractionProfile" => a::get_current_interaction_profile,
        "xrApplyHapticFeedback" => a::apply_haptic_feedback,
    )
}

/// Core 1.0 functions the host never calls (haptics, bounds, view
/// configuration properties, bound-source queries). The `openxr` crate resolves every core function
/// when it creates an instance, so they must resolve; calling one answers
/// XR_ERROR_FUNCTION_UNSUPPORTED.
const NOT_CALLED_BY_HOST: &[&str] = &[
    "xrStructureTypeToString",
    "xrGetViewConfigurationProperties",
    "xrStopHapticFeedback",
    "xrGetReferenceSpaceBoundsRect",
    "xrGetActionStateVector2f",
    "xrEnumerateBoundSourcesForAction",
    "xrGetInputSourceLocalizedName",
];

extern "system" fn not_called_by_host() -> sys::Result {
    sys::Result::ERROR_FUNCTION_UNSUPPORTED
}

/// xrGetInstanceProcAddr: with a null instance only the three
/// pre-instance functions; otherwise every implemented function of the
/// core and the enabled extensions.
unsafe extern "system" fn xr_get_instance_proc_addr(
    instance: sys::Instance,
    name: *const c_char,
    function: *mut Option<sys::pfn::VoidFunction>,
) -> sys::Result {
    // SAFETY: loader-provided pointers, null-checked.
    let (name, out) = match unsafe { (cstr(name), output(function)) } {
        (Ok(n), Ok(o)) => (n, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    *out = None;
    with_rt(|rt| {
        let exts = if instance == sys::Instance::NULL {
            if !matches!(
                name.as_str(),
                "xrEnumerateInstanceExtensionProperties"
                    | "xrEnumerateApiLayerProperties"
                    | "xrCreateInstance"
                    | "xrGetInstanceProcAddr"
            ) {
                return sys::Result::ERROR_HANDLE_INVALID;
            }
            Vec::new()
        } else {
            match &rt.instance {
                Some(i) if i.handle == instance.into_raw() => i.extensions.clone(),
                _ => return sys::Result::ERROR_HANDLE_INVALID,
            }
        };
        match lookup(&name, &exts) {
            Some(f) => {
                *out = Some(f);
                sys::Result::SUCCESS
            }
            None => sys::Result::ERROR_FUNCTION_UNSUPPORTED,
        }
    })
}
