//! [`GfxError`]: what went wrong on the GPU side (a Vulkan call, a missing
//! device feature, a shader).

use ash::vk;

/// What went wrong on the GPU side.
#[derive(Debug, thiserror::Error)]
pub enum GfxError {
    /// libvulkan could not be loaded: install a Vulkan driver (on a machine
    /// without a GPU: Debian `mesa-vulkan-drivers` for lavapipe, plus `libvulkan1`).
    #[error(
        "cannot load Vulkan ({0}); install libvulkan1 and a driver such as mesa-vulkan-drivers"
    )]
    LoadVulkan(String),
    /// A Vulkan call failed.
    #[error("{call} failed: {result}")]
    Vk {
        /// The Vulkan function.
        call: &'static str,
        /// Its result code.
        result: vk::Result,
    },
    /// No physical device supports Vulkan 1.1 with a graphics queue.
    #[error("no Vulkan 1.1 device with a graphics queue (set VK_ICD_FILENAMES to lavapipe's lvp_icd json to render on the CPU)")]
    NoDevice,
    /// No memory type fits a resource.
    #[error("no suitable Vulkan memory type")]
    NoMemoryType,
    /// A write past a buffer's end.
    #[error("buffer overflow: need {needed} bytes, buffer has {size}")]
    BufferOverflow {
        /// Bytes needed.
        needed: u64,
        /// Bytes available.
        size: u64,
    },
    /// Only 1 (mono) or 2 (stereo) views are supported.
    #[error("unsupported view count {0} (use 1 or 2)")]
    BadViewCount(u32),
    /// Image sizes must be 1..=8192.
    #[error("bad image size {width}x{height} (each side must be 1..=8192)")]
    BadExtent {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
    },
    /// A committed SPIR-V blob was malformed.
    #[error("bad SPIR-V: {0}")]
    Shader(String),
    /// OpenXR refused part of the Vulkan setup.
    #[error("OpenXR graphics setup: {0}")]
    Xr(String),
}

impl GfxError {
    pub(crate) fn vk(call: &'static str, result: vk::Result) -> Self {
        Self::Vk { call, result }
    }
}
