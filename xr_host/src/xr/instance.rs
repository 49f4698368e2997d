//! Instance creation and what the runtime and system can do.
//!
//! The instance asks for OpenXR 1.1 and falls back to 1.0 when the runtime
//! refuses the version (1.1 makes LOCAL_FLOOR and the Touch Plus, Pico 4
//! and Focus 3 profiles core). Extensions are enabled when offered:
//! the mode's own (`XR_MND_headless` + the OS's clock extension,
//! [`super::platform::CLOCK_EXTENSION`], or `XR_KHR_vulkan_enable2`), then hand tracking and its data source, hand
//! interaction, eye gaze, local floor and the vendor controller profiles.
//! With [`RunConfig::openxr_1_0`] the host behaves as an OpenXR 1.0
//! application of the Debian 12 era (API 1.0, only the mode's extensions
//! and `XR_EXT_hand_tracking`): what a validation layer built for 1.0.20
//! (Debian's `openxr-layer-corevalidation`) knows, so it reports real
//! misuse, not enum values it has never heard of (it rejects LOCAL_FLOOR).
//!
//! Offered is not supported: the system is then asked
//! (`XrSystemHandTrackingPropertiesEXT`, `XrSystemEyeGazeInteractionPropertiesEXT`)
//! and the host creates a hand tracker only where the system can track
//! hands (issue 16: Monado's `simulated` system offers the extension and
//! fails `xrCreateHandTrackerEXT`).

use openxr as xr;
use serde::{Deserialize, Serialize};

use super::{platform, RunConfig, XrHostError};
use crate::gfx::xr_raw;

/// What the runtime and its system are and can do (the `run` report).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RuntimeInfo {
    /// `runtimeName`.
    pub name: String,
    /// `runtimeVersion` as major.minor.patch.
    pub version: String,
    /// The OpenXR version the instance was created with.
    pub api_version: String,
    /// `systemName`.
    pub system: String,
    /// Extensions enabled on the instance.
    pub extensions: Vec<String>,
    /// Whether the runtime offers XR_EXT_hand_tracking.
    pub hand_tracking_offered: bool,
    /// Whether the system can track hands (`supportsHandTracking`); false
    /// when the extension is not offered.
    pub hand_tracking_supported: bool,
    /// Whether the runtime says where joints come from
    /// (XR_EXT_hand_tracking_data_source).
    pub hand_data_source: bool,
    /// `supportsEyeGazeInteraction` (None: extension not offered).
    pub eye_gaze: Option<bool>,
    /// Environment blend modes, the runtime's preference first.
    pub blend_modes: Vec<String>,
}

/// A created instance with its system and what was enabled.
pub struct InstanceCaps {
    /// The instance.
    pub instance: xr::Instance,
    /// The head-mounted system.
    pub system: xr::SystemId,
    /// `[major, minor]` of the instance's API version.
    pub api: [u16; 2],
    /// Create hand trackers (the extension is enabled and the system can
    /// track hands).
    pub hand_tracking: bool,
    /// XR_EXT_hand_tracking_data_source is enabled.
    pub hand_data_source: bool,
    /// XR_EXT_local_floor is enabled (or the instance is 1.1).
    pub local_floor: bool,
    /// Names of the enabled extensions.
    pub enabled: Vec<String>,
    /// For the report.
    pub info: RuntimeInfo,
}

fn version_string(v: xr::Version) -> String {
    format!("{}.{}.{}", v.major(), v.minor(), v.patch())
}

/// Enables the optional extensions that are offered (only hand tracking
/// in 1.0 mode); returns their names.
fn optional(
    available: &xr::ExtensionSet,
    want: &mut xr::ExtensionSet,
    only_1_0: bool,
) -> Vec<&'static str> {
    let mut on = Vec::new();
    if only_1_0 {
        if available.ext_hand_tracking {
            want.ext_hand_tracking = true;
            on.push("XR_EXT_hand_tracking");
        }
        return on;
    }
    macro_rules! opt {
        ($($field:ident => $name:literal),* $(,)?) => {$(
            if available.$field {
                want.$field = true;
                on.push($name);
            }
        )*};
    }
    opt!(
        ext_hand_tracking => "XR_EXT_hand_tracking",
        ext_hand_tracking_data_source => "XR_EXT_hand_tracking_data_source",
        ext_hand_interaction => "XR_EXT_hand_interaction",
        ext_eye_gaze_interaction => "XR_EXT_eye_gaze_interaction",
        ext_local_floor => "XR_EXT_local_floor",
        meta_touch_controller_plus => "XR_META_touch_controller_plus",
        fb_touch_controller_pro => "XR_FB_touch_controller_pro",
        bd_controller_interaction => "XR_BD_controller_interaction",
        htc_vive_focus3_controller_interaction => "XR_HTC_vive_focus3_controller_interaction",
    );
    on
}

/// xrCreateInstance's failure: no runtime (the loader found none, or
/// could not load the one named), or another refusal.
fn instance_error(r: xr::sys::Result) -> XrHostError {
    match r {
        xr::sys::Result::ERROR_RUNTIME_UNAVAILABLE => XrHostError::NoRuntime(r),
        _ => XrHostError::call("xrCreateInstance", r),
    }
}

/// Loads the runtime through the static loader and creates an instance
/// for `headless` or Vulkan mode with every useful extension offered,
/// then asks the system what it supports.
pub fn create_instance(headless: bool, cfg: &RunConfig) -> Result<InstanceCaps, XrHostError> {
    let entry = xr::Entry::linked(&()).map_err(XrHostError::NoRuntime)?;
    let available = entry
        .enumerate_extensions()
        .map_err(XrHostError::NoRuntime)?;
    let mut want = xr::ExtensionSet::default();
    let mut enabled: Vec<String> = Vec::new();
    if headless {
        if !available.mnd_headless {
            return Err(XrHostError::MissingExtension("XR_MND_headless"));
        }
        if !platform::enable_clock(&available, &mut want) {
            return Err(XrHostError::MissingExtension(platform::CLOCK_EXTENSION));
        }
        want.mnd_headless = true;
        enabled.push("XR_MND_headless".into());
        enabled.push(platform::CLOCK_EXTENSION.into());
    } else {
        if !available.khr_vulkan_enable2 {
            return Err(XrHostError::NoVulkan);
        }
        want.khr_vulkan_enable2 = true;
        enabled.push("XR_KHR_vulkan_enable2".into());
    }
    enabled.extend(
        optional(&available, &mut want, cfg.openxr_1_0)
            .into_iter()
            .map(String::from),
    );
    let app = |api| xr::ApplicationInfo {
        application_name: "shapewright-xr",
        application_version: 1,
        engine_name: "shapewright",
        engine_version: 1,
        api_version: api,
    };
    let first = if cfg.openxr_1_0 {
        Err(xr::sys::Result::ERROR_API_VERSION_UNSUPPORTED)
    } else {
        entry.create_instance(&app(xr::Version::new(1, 1, 0)), &want, &[], &())
    };
    let (instance, api) = match first {
        Ok(i) => (i, [1, 1]),
        Err(xr::sys::Result::ERROR_API_VERSION_UNSUPPORTED) => (
            entry
                .create_instance(&app(xr::Version::new(1, 0, 0)), &want, &[], &())
                .map_err(instance_error)?,
            [1, 0],
        ),
        Err(r) => return Err(instance_error(r)),
    };
    let props = instance
        .properties()
        .map_err(|r| XrHostError::call("xrGetInstanceProperties", r))?;
    let system = instance
        .system(xr::FormFactor::HEAD_MOUNTED_DISPLAY)
        .map_err(|r| XrHostError::call("xrGetSystem", r))?;
    let caps = xr_raw::system_caps(
        &instance,
        system,
        want.ext_hand_tracking,
        want.ext_eye_gaze_interaction,
    )
    .map_err(|r| XrHostError::call("xrGetSystemProperties", r))?;
    let view = xr::ViewConfigurationType::PRIMARY_STEREO;
    let blend_modes = instance
        .enumerate_environment_blend_modes(system, view)
        .map(|m| m.iter().map(|b| format!("{b:?}")).collect())
        .unwrap_or_default();
    let hand_tracking = caps.hand_tracking == Some(true);
    let info = RuntimeInfo {
        name: props.runtime_name,
        version: version_string(props.runtime_version),
        api_version: format!("{}.{}", api[0], api[1]),
        system: caps.name,
        extensions: enabled.clone(),
        hand_tracking_offered: want.ext_hand_tracking,
        hand_tracking_supported: hand_tracking,
        hand_data_source: want.ext_hand_tracking_data_source,
        eye_gaze: caps.eye_gaze,
        blend_modes,
    };
    Ok(InstanceCaps {
        instance,
        system,
        api,
        hand_tracking,
        hand_data_source: hand_tracking && want.ext_hand_tracking_data_source,
        local_floor: want.ext_local_floor || api >= [1, 1],
        enabled,
        info,
    })
}
