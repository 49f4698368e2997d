//! What differs by operating system in the OpenXR host, and only that
//! (issue 32: platforms are a build matter, not a code fork):
//!
//! - which runtimes to name when none is active ([`install_hint`]): PC VR
//!   on Windows comes through SteamVR, Meta Quest Link, Virtual Desktop,
//!   Pico Connect or Windows Mixed Reality; on Linux through Monado,
//!   WiVRn, ALVR or SteamVR; each makes itself the active runtime (the
//!   registry key `HKLM\SOFTWARE\Khronos\OpenXR\1\ActiveRuntime` on
//!   Windows, `active_runtime.json` under the XDG config directories on
//!   Linux), or `XR_RUNTIME_JSON` names a runtime's manifest;
//! - what to say when the runtime has no Vulkan ([`no_vulkan_hint`]):
//!   Windows Mixed Reality's own runtime offers Direct3D only;
//! - where the user's caches go ([`cache_home`]): `%LOCALAPPDATA%` on
//!   Windows, `$XDG_CACHE_HOME` or `~/.cache` elsewhere;
//! - which extension turns the OS clock into `XrTime` for the headless
//!   mode ([`CLOCK_EXTENSION`]): the openxr crate's `Instance::now` calls
//!   `xrConvertWin32PerformanceCounterToTimeKHR` on Windows and
//!   `xrConvertTimespecTimeToTimeKHR` elsewhere.

use openxr as xr;

/// The extension `Instance::now` needs on this OS.
#[cfg(windows)]
pub const CLOCK_EXTENSION: &str = "XR_KHR_win32_convert_performance_counter_time";
/// The extension `Instance::now` needs on this OS.
#[cfg(not(windows))]
pub const CLOCK_EXTENSION: &str = "XR_KHR_convert_timespec_time";

/// Enables [`CLOCK_EXTENSION`] in `want` if `available` offers it.
pub fn enable_clock(available: &xr::ExtensionSet, want: &mut xr::ExtensionSet) -> bool {
    #[cfg(windows)]
    let (offered, flag) = (
        available.khr_win32_convert_performance_counter_time,
        &mut want.khr_win32_convert_performance_counter_time,
    );
    #[cfg(not(windows))]
    let (offered, flag) = (
        available.khr_convert_timespec_time,
        &mut want.khr_convert_timespec_time,
    );
    *flag = offered;
    offered
}

/// The user's cache directory: `$XDG_CACHE_HOME` if set (on any OS),
/// else `%LOCALAPPDATA%` on Windows and `$HOME/.cache` elsewhere.
pub fn cache_home() -> Option<std::path::PathBuf> {
    use std::path::PathBuf;
    let var = |k| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    if let Some(d) = var("XDG_CACHE_HOME") {
        return Some(d);
    }
    if cfg!(windows) {
        var("LOCALAPPDATA")
    } else {
        var("HOME").map(|h| h.join(".cache"))
    }
}

/// The runtimes a user of this OS would install.
#[cfg(windows)]
const RUNTIMES: &str = "SteamVR (Settings > OpenXR > Set SteamVR as OpenXR runtime), \
     Meta Quest Link (Meta Horizon Link app: Settings > General > OpenXR Runtime), \
     Virtual Desktop (its VDXR runtime), Pico Connect, or Windows Mixed Reality \
     (with a WMR headset use SteamVR: WMR's own runtime has no Vulkan)";
/// The runtimes a user of this OS would install.
#[cfg(not(windows))]
const RUNTIMES: &str = "Monado (monado-service), WiVRn, ALVR or SteamVR \
     (each writes openxr/1/active_runtime.json under $XDG_CONFIG_HOME or /etc/xdg)";

/// What to do when no runtime could be loaded: the runtimes to install,
/// and what `XR_RUNTIME_JSON` says if it is set.
pub fn install_hint() -> String {
    let env = match std::env::var_os("XR_RUNTIME_JSON") {
        Some(p) if !std::path::Path::new(&p).is_file() => format!(
            " XR_RUNTIME_JSON is set to {}, which is not a file: fix or unset it.",
            p.to_string_lossy()
        ),
        Some(p) => format!(
            " XR_RUNTIME_JSON names {}, which the OpenXR loader could not load.",
            p.to_string_lossy()
        ),
        None => String::new(),
    };
    format!(
        "Install an OpenXR runtime for your headset and make it the active one: {RUNTIMES}; \
         or set XR_RUNTIME_JSON to a runtime's manifest (.json).{env}"
    )
}

/// What to say when the runtime offers no `XR_KHR_vulkan_enable2`.
pub fn no_vulkan_hint() -> &'static str {
    if cfg!(windows) {
        "the headset host renders with Vulkan: make SteamVR, Meta Quest Link or Virtual Desktop \
         the active OpenXR runtime (Windows Mixed Reality's own runtime offers Direct3D only)"
    } else {
        "the headset host renders with Vulkan: use a runtime that offers it (Monado, WiVRn, SteamVR)"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hint_names_runtimes_and_the_manifest_variable() {
        let h = install_hint();
        let names: &[&str] = if cfg!(windows) {
            &[
                "SteamVR",
                "Meta Quest Link",
                "Virtual Desktop",
                "Windows Mixed Reality",
            ]
        } else {
            &["Monado", "SteamVR"]
        };
        for n in names {
            assert!(h.contains(n), "{h}");
        }
        assert!(h.contains("XR_RUNTIME_JSON"), "{h}");
    }

    #[test]
    fn the_clock_extension_is_the_one_instance_now_uses() {
        let mut available = xr::ExtensionSet::default();
        let mut want = xr::ExtensionSet::default();
        assert!(!enable_clock(&available, &mut want));
        available.khr_convert_timespec_time = true;
        #[cfg(windows)]
        {
            assert!(!enable_clock(&available, &mut want));
            available.khr_win32_convert_performance_counter_time = true;
            assert!(enable_clock(&available, &mut want));
            assert!(want.khr_win32_convert_performance_counter_time);
        }
        #[cfg(not(windows))]
        {
            assert!(enable_clock(&available, &mut want));
            assert!(want.khr_convert_timespec_time);
        }
    }
}
