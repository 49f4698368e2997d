//! [`XrHostError`]: what went wrong talking to the OpenXR runtime, and how
//! a runtime result is classified (lost session or instance, or failure).

use super::platform;
use openxr as xr;

/// What went wrong talking to the OpenXR runtime.
#[derive(Debug, thiserror::Error)]
pub enum XrHostError {
    /// No runtime could be loaded (none installed or active, or
    /// `XR_RUNTIME_JSON` points nowhere); the message names what to
    /// install on this OS ([`platform::install_hint`]).
    #[error("no OpenXR runtime available ({0}). {hint}", hint = platform::install_hint())]
    NoRuntime(xr::sys::Result),
    /// The runtime lacks an extension this mode needs.
    #[error("the OpenXR runtime lacks {0}, which this mode needs")]
    MissingExtension(&'static str),
    /// The runtime cannot share frames with Vulkan (no
    /// `XR_KHR_vulkan_enable2`), which the headset mode renders with.
    #[error("the OpenXR runtime lacks XR_KHR_vulkan_enable2: {hint}", hint = platform::no_vulkan_hint())]
    NoVulkan,
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

/// Whether `r` says the session or instance is lost: never a refusal to
/// fall back from, always passed up (the loop recreates what was lost).
pub(crate) fn is_loss(r: xr::sys::Result) -> bool {
    classify(r) != Failure::Other
}
