//! The runtime's state: one instance at a time, one session per instance,
//! handles are nonzero counters. Everything sits behind one mutex.

use std::collections::{HashMap, VecDeque};

use openxr_sys as sys;

use crate::script::{Keyframe, Script};

/// An action's type as created.
#[derive(Clone, Debug)]
pub struct ActionInfo {
    pub set: u64,
    pub ty: sys::ActionType,
    pub subaction_paths: Vec<u64>,
}

/// What a space is located from.
#[derive(Clone, Copy, Debug)]
pub enum SpaceKind {
    Reference(sys::ReferenceSpaceType),
    Action { action: u64, subaction: u64 },
}

#[derive(Clone, Copy, Debug)]
pub struct SpaceInfo {
    pub session: u64,
    pub kind: SpaceKind,
    pub offset: ([f32; 3], [f32; 4]),
}

#[derive(Clone, Copy, Debug)]
pub enum QueuedEvent {
    State(u64, sys::SessionState),
    InstanceLoss,
}

/// The application's Vulkan objects, as created through
/// XR_KHR_vulkan_enable2 (function tables only: the runtime never destroys
/// the app's instance or device).
pub struct VulkanState {
    pub instance: Option<ash::Instance>,
    pub physical_device: ash::vk::PhysicalDevice,
    pub device: Option<ash::Device>,
    /// Queue family from the session's graphics binding.
    pub queue_family: u32,
    /// Whether a frame was already captured (once per process).
    pub captured: bool,
}

/// A swapchain's images on the application's device.
pub struct SwapchainData {
    pub session: u64,
    pub images: Vec<(ash::vk::Image, ash::vk::DeviceMemory)>,
    pub array_size: u32,
    pub width: u32,
    pub height: u32,
    pub next: usize,
    /// Acquired, not yet released: (index, waited).
    pub acquired: std::collections::VecDeque<(usize, bool)>,
    pub released_once: bool,
    /// The image index released last (what a layer shows).
    pub last_released: usize,
    pub format: ash::vk::Format,
}

/// Frame-loop bookkeeping for graphics sessions.
#[derive(Default)]
pub struct FrameData {
    pub waited: bool,
    pub begun: bool,
    pub ended: u64,
    pub projection_layers: u64,
}

pub struct SessionData {
    pub handle: u64,
    /// The last state delivered to the application through xrPollEvent.
    pub state: sys::SessionState,
    pub running: bool,
    pub exit_requested: bool,
    /// LOSS_PENDING was delivered: calls now return ERROR_SESSION_LOST.
    pub lost: bool,
    pub attached: Vec<u64>,
    /// Input as of the last xrSyncActions (None: not focused / never synced).
    pub synced: Option<Keyframe>,
    /// A Vulkan session (else headless).
    pub graphics: bool,
    pub frame: FrameData,
    /// LOCAL's origin in STAGE: the head's position and yaw at the first
    /// locate (None until then).
    pub local_origin: Option<crate::script::pose::Pose>,
    /// Haptic pulses applied per hand.
    pub haptics: [u64; 2],
}

pub struct InstanceData {
    pub handle: u64,
    pub lost: bool,
    pub extensions: Vec<String>,
    pub paths: Vec<String>,
    pub action_sets: HashMap<u64, String>,
    pub actions: HashMap<u64, ActionInfo>,
    /// profile path -> (action, binding path)
    pub bindings: HashMap<u64, Vec<(u64, u64)>>,
    pub session: Option<SessionData>,
    pub spaces: HashMap<u64, SpaceInfo>,
    pub trackers: HashMap<u64, (u64, sys::HandEXT)>,
    pub events: VecDeque<QueuedEvent>,
    pub vulkan: Option<VulkanState>,
    pub requirements_queried: bool,
    pub swapchains: HashMap<u64, SwapchainData>,
}

pub struct Runtime {
    pub script: Script,
    pub next_handle: u64,
    pub instance: Option<InstanceData>,
    /// xrSyncActions calls since the process loaded the runtime.
    pub step: u64,
    pub fired: Vec<bool>,
    pub refuse_remaining: u32,
    pub instances_created: u32,
}

impl Runtime {
    pub const fn new() -> Self {
        Self {
            script: Script::base(),
            next_handle: 1,
            instance: None,
            step: 0,
            fired: Vec::new(),
            refuse_remaining: 0,
            instances_created: 0,
        }
    }

    pub fn handle(&mut self) -> u64 {
        let h = self.next_handle;
        self.next_handle += 1;
        h
    }
}

impl InstanceData {
    pub fn path(&self, p: u64) -> Option<&str> {
        (p as usize)
            .checked_sub(1)
            .and_then(|i| self.paths.get(i))
            .map(|s| s.as_str())
    }
    pub fn path_id(&mut self, s: &str) -> u64 {
        if let Some(i) = self.paths.iter().position(|x| x == s) {
            return i as u64 + 1;
        }
        self.paths.push(s.to_string());
        self.paths.len() as u64
    }
}

/// Checks the path grammar of the spec (§6.1): starts with '/', no
/// trailing '/', no empty components, only [a-z0-9-_.] inside.
pub fn path_well_formed(s: &str) -> bool {
    s.len() > 1
        && s.starts_with('/')
        && !s.ends_with('/')
        && !s.contains("//")
        && s[1..].split('/').all(|c| {
            !c.is_empty()
                && c != "."
                && c != ".."
                && c.chars()
                    .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || "-_.".contains(ch))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_grammar_follows_the_spec() {
        for ok in [
            "/user/hand/left",
            "/interaction_profiles/khr/simple_controller",
            "/a-b_c.d",
        ] {
            assert!(path_well_formed(ok), "{ok}");
        }
        for bad in [
            "",
            "/",
            "user/hand",
            "/user/",
            "/user//hand",
            "/User",
            "/a/./b",
            "/a/../b",
            "/a b",
        ] {
            assert!(!path_well_formed(bad), "{bad}");
        }
    }
}
