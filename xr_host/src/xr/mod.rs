//! The OpenXR host: instance creation (the `openxr` crate's statically
//! linked loader 1.1.54), actions from the core's binding data, the session lifecycle
//! as types, sanitized input handed to a [`FrameSink`], and the headless
//! (`XR_MND_headless`) loop. Session creation, being unsafe, lives in
//! `crate::gfx::xr_bridge`.

pub mod actions;
pub mod events;
pub mod headless;
pub mod headset;
pub mod input;
pub mod lifecycle;

pub use headless::run_headless;
pub use headset::run_headset;
pub use input::{CollectSink, FrameSink, HandInput, InputFrame, LifecycleEvent, Pose};

use std::time::Duration;

use openxr as xr;

/// What went wrong talking to the OpenXR runtime.
#[derive(Debug, thiserror::Error)]
pub enum XrHostError {
    /// No runtime could be loaded (none installed, or `XR_RUNTIME_JSON`
    /// points nowhere).
    #[error(
        "no OpenXR runtime available ({0}); install one or set XR_RUNTIME_JSON to its manifest"
    )]
    NoRuntime(xr::sys::Result),
    /// The runtime lacks an extension this mode needs.
    #[error("the OpenXR runtime lacks {0}, which this mode needs")]
    MissingExtension(&'static str),
    /// An OpenXR call failed.
    #[error("{call} failed: {result}")]
    Call {
        /// What the host was doing.
        call: &'static str,
        /// The runtime's result code.
        result: xr::sys::Result,
    },
    /// The Vulkan side of the headset session failed.
    #[error("graphics: {0}")]
    Graphics(String),
    /// Retries were exhausted or the runtime stalled.
    #[error("giving up: {0}")]
    GaveUp(String),
}

impl XrHostError {
    pub(crate) fn call(call: &'static str, result: xr::sys::Result) -> Self {
        Self::Call { call, result }
    }
    /// Worth retrying instance creation after this (the runtime may come back).
    pub fn is_retryable(&self) -> bool {
        use xr::sys::Result as R;
        match self {
            Self::NoRuntime(r) | Self::Call { result: r, .. } => matches!(
                *r,
                R::ERROR_INSTANCE_LOST
                    | R::ERROR_RUNTIME_UNAVAILABLE
                    | R::ERROR_RUNTIME_FAILURE
                    | R::ERROR_FORM_FACTOR_UNAVAILABLE
            ),
            _ => false,
        }
    }
}

/// How an OpenXR error affects the loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Failure {
    SessionLost,
    InstanceLost,
    Other,
}

pub(crate) fn classify(r: xr::sys::Result) -> Failure {
    match r {
        xr::sys::Result::ERROR_SESSION_LOST => Failure::SessionLost,
        xr::sys::Result::ERROR_INSTANCE_LOST => Failure::InstanceLost,
        _ => Failure::Other,
    }
}

/// Settings of a run.
#[derive(Clone, Debug)]
pub struct RunConfig {
    /// Stop (request exit) after this many input frames.
    pub max_frames: Option<u64>,
    /// Stop (request exit) after this long.
    pub max_duration: Option<Duration>,
    /// Headless tick period (default 11.1 ms, 90 Hz).
    pub frame_period: Duration,
    /// Recreate the session after LOSS_PENDING (else stop).
    pub recreate_lost_sessions: bool,
    /// At most this many session recreations per instance.
    pub max_session_recreations: u32,
    /// At most this many instance re-creations (after loss or failure).
    pub max_instance_retries: u32,
    /// Wait between instance attempts.
    pub retry_delay: Duration,
    /// Give up if a session is not READY this long after creation.
    pub stall_timeout: Duration,
}

impl Default for RunConfig {
    fn default() -> Self {
        Self {
            max_frames: None,
            max_duration: None,
            frame_period: Duration::from_micros(11_111),
            recreate_lost_sessions: true,
            max_session_recreations: 8,
            max_instance_retries: 5,
            retry_delay: Duration::from_millis(200),
            stall_timeout: Duration::from_secs(10),
        }
    }
}

/// What happened during a run.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunReport {
    /// Input frames handed to the sink.
    pub frames: u64,
    /// Poses dropped (VALID bits unset, NaN, non-unit quaternion).
    pub poses_dropped: u64,
    /// Hand joints dropped.
    pub joints_dropped: u64,
    /// Instances created.
    pub instances_created: u32,
    /// Failed instance creations that were retried.
    pub instance_retries: u32,
    /// Instances lost.
    pub instance_losses: u32,
    /// Sessions created.
    pub sessions_created: u32,
    /// Sessions lost.
    pub session_losses: u32,
    /// Session states in order.
    pub states: Vec<String>,
    /// Whether any session reached FOCUSED.
    pub reached_focused: bool,
    /// Events the runtime reported lost.
    pub events_lost: u64,
    /// Interaction profiles the runtime accepted bindings for.
    pub profiles: Vec<String>,
    /// Why the run ended.
    pub exit_reason: String,
    /// CPU time of each frame's input step, microseconds.
    pub frame_cpu_us: Vec<f64>,
}

impl RunReport {
    /// The `q` quantile (0..1) of per-frame CPU time in microseconds.
    pub fn frame_cpu_quantile(&self, q: f64) -> Option<f64> {
        quantile(&self.frame_cpu_us, q)
    }
}

/// The `q` quantile (0..1, nearest rank) of `v`; None when empty.
pub fn quantile(v: &[f64], q: f64) -> Option<f64> {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let i = ((v.len().checked_sub(1)?) as f64 * q.clamp(0.0, 1.0)).round() as usize;
    v.get(i).copied()
}

/// A created instance with its system and what was enabled.
pub struct InstanceCaps {
    /// The instance.
    pub instance: xr::Instance,
    /// The head-mounted system.
    pub system: xr::SystemId,
    /// Whether XR_EXT_hand_tracking is enabled.
    pub hand_tracking: bool,
    /// Names of the enabled extensions.
    pub enabled: Vec<String>,
    /// The runtime's name.
    pub runtime_name: String,
}

/// Loads the runtime through the static loader and creates an instance
/// with the extensions the mode needs (`headless`: XR_MND_headless and
/// XR_KHR_convert_timespec_time; otherwise XR_KHR_vulkan_enable2) plus
/// hand tracking / hand interaction when offered.
pub fn create_instance(_cfg: &RunConfig, headless: bool) -> Result<InstanceCaps, XrHostError> {
    let entry = xr::Entry::linked(&()).map_err(XrHostError::NoRuntime)?;
    let available = entry
        .enumerate_extensions()
        .map_err(XrHostError::NoRuntime)?;
    let mut want = xr::ExtensionSet::default();
    let mut enabled = Vec::new();
    if headless {
        if !available.mnd_headless {
            return Err(XrHostError::MissingExtension("XR_MND_headless"));
        }
        if !available.khr_convert_timespec_time {
            return Err(XrHostError::MissingExtension(
                "XR_KHR_convert_timespec_time",
            ));
        }
        want.mnd_headless = true;
        want.khr_convert_timespec_time = true;
        enabled.push("XR_MND_headless".to_string());
        enabled.push("XR_KHR_convert_timespec_time".to_string());
    } else {
        if !available.khr_vulkan_enable2 {
            return Err(XrHostError::MissingExtension("XR_KHR_vulkan_enable2"));
        }
        want.khr_vulkan_enable2 = true;
        enabled.push("XR_KHR_vulkan_enable2".to_string());
    }
    if available.ext_hand_tracking {
        want.ext_hand_tracking = true;
        enabled.push("XR_EXT_hand_tracking".to_string());
    }
    if available.ext_hand_interaction {
        want.ext_hand_interaction = true;
        enabled.push("XR_EXT_hand_interaction".to_string());
    }
    let app = xr::ApplicationInfo {
        application_name: "shapewright-xr",
        application_version: 1,
        engine_name: "shapewright",
        engine_version: 1,
        api_version: xr::Version::new(1, 0, 0),
    };
    let instance = entry
        .create_instance(&app, &want, &[], &())
        .map_err(|r| XrHostError::call("xrCreateInstance", r))?;
    let runtime_name = instance
        .properties()
        .map(|p| p.runtime_name)
        .unwrap_or_default();
    let system = instance
        .system(xr::FormFactor::HEAD_MOUNTED_DISPLAY)
        .map_err(|r| XrHostError::call("xrGetSystem", r))?;
    Ok(InstanceCaps {
        instance,
        system,
        hand_tracking: want.ext_hand_tracking,
        enabled,
        runtime_name,
    })
}
