//! Instance-level functions: extensions, instance, system, paths,
//! actions, bindings, time.

use std::ffi::c_char;

use openxr_sys as sys;
use sys::Handle as _;

use crate::script::Script;
use crate::state::{path_well_formed, ActionInfo, InstanceData, Runtime};
use crate::{cstr, done, fixed_str, input, output, with_rt, write_fixed, RUNTIME_NAME};

pub(crate) fn offered(script: &Script) -> Vec<&'static str> {
    let mut v = vec!["XR_MND_headless", "XR_KHR_convert_timespec_time"];
    if script.hand_tracking {
        v.push("XR_EXT_hand_tracking");
        if script.hand_source.is_some() {
            v.push("XR_EXT_hand_tracking_data_source");
        }
    }
    if script.local_floor {
        v.push("XR_EXT_local_floor");
    }
    if script.vulkan {
        v.push("XR_KHR_vulkan_enable2");
    }
    v
}

/// The runtime's one system (an HMD), as `xrGetSystem` hands it out.
pub(crate) const SYSTEM: u64 = 1;

/// `ERROR_SYSTEM_INVALID` unless `id` is [`SYSTEM`].
pub(crate) fn check_system(id: sys::SystemId) -> Result<(), sys::Result> {
    if id.into_raw() == SYSTEM {
        Ok(())
    } else {
        Err(sys::Result::ERROR_SYSTEM_INVALID)
    }
}

/// `ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED` unless `ty` is the one
/// view configuration the runtime offers, primary stereo.
pub(crate) fn check_stereo(ty: sys::ViewConfigurationType) -> Result<(), sys::Result> {
    if ty == sys::ViewConfigurationType::PRIMARY_STEREO {
        Ok(())
    } else {
        Err(sys::Result::ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED)
    }
}

/// The live, not-lost instance with this handle.
pub(crate) fn inst(rt: &mut Runtime, h: sys::Instance) -> Result<&mut InstanceData, sys::Result> {
    match &mut rt.instance {
        Some(i) if i.handle == h.into_raw() => {
            if i.lost {
                Err(sys::Result::ERROR_INSTANCE_LOST)
            } else {
                Ok(i)
            }
        }
        _ => Err(sys::Result::ERROR_HANDLE_INVALID),
    }
}

pub(crate) unsafe extern "system" fn enumerate_instance_extension_properties(
    layer_name: *const c_char,
    capacity: u32,
    count: *mut u32,
    props: *mut sys::ExtensionProperties,
) -> sys::Result {
    if !layer_name.is_null() {
        return sys::Result::ERROR_API_LAYER_NOT_PRESENT;
    }
    let exts = offered(&Script::from_env());
    // SAFETY: loader pointer, null-checked.
    let Ok(count) = (unsafe { output(count) }) else {
        return sys::Result::ERROR_VALIDATION_FAILURE;
    };
    *count = exts.len() as u32;
    if capacity == 0 {
        return sys::Result::SUCCESS;
    }
    if (capacity as usize) < exts.len() {
        return sys::Result::ERROR_SIZE_INSUFFICIENT;
    }
    if props.is_null() {
        return sys::Result::ERROR_VALIDATION_FAILURE;
    }
    for (k, e) in exts.iter().enumerate() {
        // SAFETY: `props` holds `capacity` >= exts.len() elements.
        let p = unsafe { &mut *props.add(k) };
        if p.ty != sys::ExtensionProperties::TYPE {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        write_fixed(&mut p.extension_name, e);
        p.extension_version = 1;
    }
    sys::Result::SUCCESS
}

pub(crate) unsafe extern "system" fn enumerate_api_layer_properties(
    _capacity: u32,
    count: *mut u32,
    _props: *mut sys::ApiLayerProperties,
) -> sys::Result {
    // SAFETY: loader pointer, null-checked.
    match unsafe { output(count) } {
        Ok(c) => {
            *c = 0;
            sys::Result::SUCCESS
        }
        Err(e) => e,
    }
}

pub(crate) unsafe extern "system" fn create_instance(
    info: *const sys::InstanceCreateInfo,
    instance: *mut sys::Instance,
) -> sys::Result {
    // SAFETY: loader pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(instance)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    if info.ty != sys::InstanceCreateInfo::TYPE {
        return sys::Result::ERROR_VALIDATION_FAILURE;
    }
    let v = info.application_info.api_version;
    if v.major() != 1 || v.minor() > 0 {
        return sys::Result::ERROR_API_VERSION_UNSUPPORTED;
    }
    if fixed_str(&info.application_info.application_name).is_none_or(|s| s.is_empty()) {
        return sys::Result::ERROR_NAME_INVALID;
    }
    if info.enabled_api_layer_count > 0 {
        return sys::Result::ERROR_API_LAYER_NOT_PRESENT;
    }
    let mut wanted = Vec::new();
    for k in 0..info.enabled_extension_count as usize {
        if info.enabled_extension_names.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: the array holds enabled_extension_count string pointers.
        match unsafe { cstr(*info.enabled_extension_names.add(k)) } {
            Ok(s) => wanted.push(s),
            Err(e) => return e,
        }
    }
    let script = Script::from_env();
    let exts = offered(&script);
    if wanted.iter().any(|w| !exts.contains(&w.as_str())) {
        return sys::Result::ERROR_EXTENSION_NOT_PRESENT;
    }
    with_rt(|rt| {
        if rt.instance.is_some() {
            return sys::Result::ERROR_LIMIT_REACHED;
        }
        if rt.refuse_remaining > 0 {
            rt.refuse_remaining -= 1;
            return sys::Result::ERROR_RUNTIME_FAILURE;
        }
        if rt.fired.len() != script.faults.len() {
            rt.fired = vec![false; script.faults.len()];
        }
        rt.script = script;
        let h = rt.handle();
        rt.instances_created += 1;
        rt.instance = Some(InstanceData {
            handle: h,
            lost: false,
            extensions: wanted,
            paths: Vec::new(),
            action_sets: Default::default(),
            actions: Default::default(),
            bindings: Default::default(),
            session: None,
            spaces: Default::default(),
            trackers: Default::default(),
            events: Default::default(),
            vulkan: None,
            requirements_queried: false,
            swapchains: Default::default(),
        });
        *out = sys::Instance::from_raw(h);
        sys::Result::SUCCESS
    })
}

pub(crate) unsafe extern "system" fn destroy_instance(instance: sys::Instance) -> sys::Result {
    with_rt(|rt| match &rt.instance {
        Some(i) if i.handle == instance.into_raw() => {
            rt.instance = None;
            sys::Result::SUCCESS
        }
        _ => sys::Result::ERROR_HANDLE_INVALID,
    })
}

pub(crate) unsafe extern "system" fn get_instance_properties(
    instance: sys::Instance,
    props: *mut sys::InstanceProperties,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let props = match unsafe { output(props) } {
        Ok(p) => p,
        Err(e) => return e,
    };
    with_rt(|rt| {
        done(inst(rt, instance).map(|_| {
            props.runtime_version = sys::Version::new(0, 1, 0);
            write_fixed(&mut props.runtime_name, RUNTIME_NAME);
            sys::Result::SUCCESS
        }))
    })
}

pub(crate) unsafe extern "system" fn result_to_string(
    instance: sys::Instance,
    value: sys::Result,
    buffer: *mut c_char,
) -> sys::Result {
    if buffer.is_null() {
        return sys::Result::ERROR_VALIDATION_FAILURE;
    }
    let s = format!("XR_{value:?}");
    // SAFETY: the spec sizes the buffer XR_MAX_RESULT_STRING_SIZE.
    let dst = unsafe { std::slice::from_raw_parts_mut(buffer, sys::MAX_RESULT_STRING_SIZE) };
    write_fixed(dst, &s);
    with_rt(|rt| done(inst(rt, instance).map(|_| sys::Result::SUCCESS)))
}

pub(crate) unsafe extern "system" fn get_system(
    instance: sys::Instance,
    info: *const sys::SystemGetInfo,
    system: *mut sys::SystemId,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(system)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|_| {
            if info.ty != sys::SystemGetInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if info.form_factor != sys::FormFactor::HEAD_MOUNTED_DISPLAY {
                return Err(sys::Result::ERROR_FORM_FACTOR_UNSUPPORTED);
            }
            *out = sys::SystemId::from_raw(SYSTEM);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn get_system_properties(
    instance: sys::Instance,
    system: sys::SystemId,
    props: *mut sys::SystemProperties,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let props = match unsafe { output(props) } {
        Ok(p) => p,
        Err(e) => return e,
    };
    with_rt(|rt| {
        let rt_hands_supported = rt.script.hands_supported;
        done(inst(rt, instance).and_then(|i| {
            check_system(system)?;
            props.system_id = system;
            props.vendor_id = 0;
            write_fixed(&mut props.system_name, RUNTIME_NAME);
            props.tracking_properties.orientation_tracking = sys::TRUE;
            props.tracking_properties.position_tracking = sys::TRUE;
            props.graphics_properties.max_layer_count = 0;
            // Chained outputs: hand-tracking support, the only one we know.
            let mut next = props.next as *mut sys::BaseOutStructure;
            while !next.is_null() {
                // SAFETY: the chain is valid per the spec: every element
                // starts with type and next.
                let ty = unsafe { (*next).ty };
                if ty == sys::SystemHandTrackingPropertiesEXT::TYPE {
                    if !i.extensions.iter().any(|e| e == "XR_EXT_hand_tracking") {
                        return Err(sys::Result::ERROR_VALIDATION_FAILURE);
                    }
                    // SAFETY: the type says which struct this is.
                    let h = unsafe { &mut *(next as *mut sys::SystemHandTrackingPropertiesEXT) };
                    h.supports_hand_tracking = rt_hands_supported.into();
                }
                // SAFETY: as above.
                next = unsafe { (*next).next };
            }
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn string_to_path(
    instance: sys::Instance,
    s: *const c_char,
    path: *mut sys::Path,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (s, out) = match unsafe { (cstr(s), output(path)) } {
        (Ok(s), Ok(o)) => (s, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|i| {
            if !path_well_formed(&s) {
                return Err(sys::Result::ERROR_PATH_FORMAT_INVALID);
            }
            *out = sys::Path::from_raw(i.path_id(&s));
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn path_to_string(
    instance: sys::Instance,
    path: sys::Path,
    capacity: u32,
    count: *mut u32,
    buffer: *mut c_char,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let count = match unsafe { output(count) } {
        Ok(c) => c,
        Err(e) => return e,
    };
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|i| {
            let s = i
                .path(path.into_raw())
                .ok_or(sys::Result::ERROR_PATH_INVALID)?
                .to_string();
            *count = s.len() as u32 + 1;
            if capacity == 0 {
                return Ok(sys::Result::SUCCESS);
            }
            if capacity < *count {
                return Err(sys::Result::ERROR_SIZE_INSUFFICIENT);
            }
            if buffer.is_null() {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            // SAFETY: the buffer holds `capacity` >= len + 1 chars.
            let dst = unsafe { std::slice::from_raw_parts_mut(buffer, capacity as usize) };
            write_fixed(dst, &s);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

fn any_attached(i: &InstanceData) -> bool {
    i.session.as_ref().is_some_and(|s| !s.attached.is_empty())
}

fn name_ok(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || "-_.".contains(c))
}

pub(crate) unsafe extern "system" fn create_action_set(
    instance: sys::Instance,
    info: *const sys::ActionSetCreateInfo,
    set: *mut sys::ActionSet,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(set)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let h = rt.handle();
        done(inst(rt, instance).and_then(|i| {
            if info.ty != sys::ActionSetCreateInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let name = fixed_str(&info.action_set_name).ok_or(sys::Result::ERROR_NAME_INVALID)?;
            let loc = fixed_str(&info.localized_action_set_name).unwrap_or_default();
            if !name_ok(&name) {
                return Err(sys::Result::ERROR_PATH_FORMAT_INVALID);
            }
            if loc.is_empty() {
                return Err(sys::Result::ERROR_LOCALIZED_NAME_INVALID);
            }
            if i.action_sets.values().any(|n| *n == name) {
                return Err(sys::Result::ERROR_NAME_DUPLICATED);
            }
            i.action_sets.insert(h, name);
            *out = sys::ActionSet::from_raw(h);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn destroy_action_set(set: sys::ActionSet) -> sys::Result {
    with_rt(|rt| {
        match rt
            .instance
            .as_mut()
            .and_then(|i| i.action_sets.remove(&set.into_raw()).map(|_| i))
        {
            Some(i) => {
                i.actions.retain(|_, a| a.set != set.into_raw());
                sys::Result::SUCCESS
            }
            None => sys::Result::ERROR_HANDLE_INVALID,
        }
    })
}

pub(crate) unsafe extern "system" fn create_action(
    set: sys::ActionSet,
    info: *const sys::ActionCreateInfo,
    action: *mut sys::Action,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(action)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    let mut subs = Vec::new();
    for k in 0..info.count_subaction_paths as usize {
        if info.subaction_paths.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: the array holds count_subaction_paths paths.
        subs.push(unsafe { *info.subaction_paths.add(k) }.into_raw());
    }
    with_rt(|rt| {
        let h = rt.handle();
        let Some(i) = rt
            .instance
            .as_mut()
            .filter(|i| i.action_sets.contains_key(&set.into_raw()))
        else {
            return sys::Result::ERROR_HANDLE_INVALID;
        };
        if i.lost {
            return sys::Result::ERROR_INSTANCE_LOST;
        }
        if info.ty != sys::ActionCreateInfo::TYPE {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        if any_attached(i) {
            return sys::Result::ERROR_ACTIONSETS_ALREADY_ATTACHED;
        }
        let Some(name) = fixed_str(&info.action_name).filter(|n| name_ok(n)) else {
            return sys::Result::ERROR_PATH_FORMAT_INVALID;
        };
        let _ = name;
        for s in &subs {
            match i.path(*s) {
                Some("/user/hand/left" | "/user/hand/right" | "/user/head" | "/user/gamepad") => {}
                Some(_) => return sys::Result::ERROR_PATH_UNSUPPORTED,
                None => return sys::Result::ERROR_PATH_INVALID,
            }
        }
        i.actions.insert(
            h,
            ActionInfo {
                set: set.into_raw(),
                ty: info.action_type,
                subaction_paths: subs.clone(),
            },
        );
        *out = sys::Action::from_raw(h);
        sys::Result::SUCCESS
    })
}

pub(crate) unsafe extern "system" fn destroy_action(action: sys::Action) -> sys::Result {
    with_rt(|rt| {
        match rt
            .instance
            .as_mut()
            .and_then(|i| i.actions.remove(&action.into_raw()))
        {
            Some(_) => sys::Result::SUCCESS,
            None => sys::Result::ERROR_HANDLE_INVALID,
        }
    })
}

/// Profiles this runtime knows (others: XR_ERROR_PATH_UNSUPPORTED).
const KNOWN_PROFILES: &[&str] = &[
    "/interaction_profiles/khr/simple_controller",
    "/interaction_profiles/oculus/touch_controller",
    "/interaction_profiles/valve/index_controller",
    "/interaction_profiles/htc/vive_controller",
    "/interaction_profiles/microsoft/motion_controller",
];

pub(crate) unsafe extern "system" fn suggest_interaction_profile_bindings(
    instance: sys::Instance,
    info: *const sys::InteractionProfileSuggestedBinding,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let info = match unsafe { input(info) } {
        Ok(i) => i,
        Err(e) => return e,
    };
    let mut pairs = Vec::new();
    for k in 0..info.count_suggested_bindings as usize {
        if info.suggested_bindings.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: the array holds count_suggested_bindings entries.
        let b = unsafe { *info.suggested_bindings.add(k) };
        pairs.push((b.action.into_raw(), b.binding.into_raw()));
    }
    with_rt(|rt| {
        let refused = rt.script.refuse.profiles.clone();
        done(inst(rt, instance).and_then(|i| {
            if info.ty != sys::InteractionProfileSuggestedBinding::TYPE || pairs.is_empty() {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let profile = i
                .path(info.interaction_profile.into_raw())
                .ok_or(sys::Result::ERROR_PATH_INVALID)?;
            if !KNOWN_PROFILES.contains(&profile) {
                return Err(sys::Result::ERROR_PATH_UNSUPPORTED);
            }
            if refused.iter().any(|p| p == profile) {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if any_attached(i) {
                return Err(sys::Result::ERROR_ACTIONSETS_ALREADY_ATTACHED);
            }
            for (a, p) in &pairs {
                if !i.actions.contains_key(a) {
                    return Err(sys::Result::ERROR_HANDLE_INVALID);
                }
                let path = i.path(*p).ok_or(sys::Result::ERROR_PATH_INVALID)?;
                let ok = ["/user/hand/left/", "/user/hand/right/"].iter().any(|u| {
                    path.strip_prefix(u)
                        .is_some_and(|r| r.starts_with("input/") || r.starts_with("output/"))
                });
                if !ok {
                    return Err(sys::Result::ERROR_PATH_UNSUPPORTED);
                }
            }
            i.bindings
                .insert(info.interaction_profile.into_raw(), pairs.clone());
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn convert_timespec_time_to_time(
    instance: sys::Instance,
    ts: *const libc::timespec,
    time: *mut sys::Time,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (ts, out) = match unsafe { (input(ts), output(time)) } {
        (Ok(t), Ok(o)) => (t, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let stepped = rt
            .script
            .step_ns
            .map(|d| 1_000_000_000i64.saturating_add(d.saturating_mul(rt.step as i64)));
        done(inst(rt, instance).and_then(|_| {
            if let Some(t) = stepped {
                *out = sys::Time::from_nanos(t);
                return Ok(sys::Result::SUCCESS);
            }
            #[allow(clippy::useless_conversion)] // time_t and c_long are i64 on LP64 only
            let (sec, nsec) = (i64::from(ts.tv_sec), i64::from(ts.tv_nsec));
            if sec < 0 || !(0..1_000_000_000).contains(&nsec) {
                return Err(sys::Result::ERROR_TIME_INVALID);
            }
            *out = sys::Time::from_nanos(
                sec.saturating_mul(1_000_000_000)
                    .saturating_add(nsec)
                    .max(1),
            );
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn convert_time_to_timespec_time(
    instance: sys::Instance,
    time: sys::Time,
    ts: *mut libc::timespec,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let out = match unsafe { output(ts) } {
        Ok(o) => o,
        Err(e) => return e,
    };
    with_rt(|rt| {
        done(inst(rt, instance).and_then(|_| {
            let n = time.as_nanos();
            if n <= 0 {
                return Err(sys::Result::ERROR_TIME_INVALID);
            }
            out.tv_sec = (n / 1_000_000_000) as libc::time_t;
            out.tv_nsec = (n % 1_000_000_000) as libc::c_long;
            Ok(sys::Result::SUCCESS)
        }))
    })
}
