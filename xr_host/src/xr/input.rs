//! What the frame loop hands to the rest of the host: input frames in the
//! core's own types ([`shapewright::interact::InputFrame`]), lifecycle
//! notifications, and the [`FrameSink`] that receives them.
//!
//! The host does not judge input. It copies what the runtime reported (the
//! VALID bits as `*_valid` flags, action values as they are, joints with
//! their flags) into the core's frame; the core's one
//! [`shapewright::interact::Sanitizer`] drops what is unusable and counts
//! it. The only rule applied here is the spec's: the contents of a pose
//! whose VALID bits are unset are undefined, so such a pose is written as
//! the identity with its flag unset (or `None` for the head), and the core
//! never sees the runtime's leftovers.

use serde::{Deserialize, Serialize};
use shapewright::interact::{InputFrame, SanitizerStats};

use crate::gfx::Scene;

/// Lifecycle notifications (for autosave on session loss and the like).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LifecycleEvent {
    /// The session changed state (the OpenXR state name).
    State(String),
    /// The session was lost (LOSS_PENDING or ERROR_SESSION_LOST).
    SessionLost,
    /// The instance was lost; the host will retry.
    InstanceLost,
    /// A new session was created (after start or recreation).
    SessionCreated,
    /// The host asked the runtime to end the session (a signal, a limit).
    ExitRequested(String),
    /// The interaction profile bound to a hand changed (after a sync).
    ProfileBound {
        /// `/user/hand/left` or `/user/hand/right`.
        hand: String,
        /// The profile path, or None when nothing is bound.
        profile: Option<String>,
    },
}

/// A haptic pulse the sink asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Haptic {
    /// 0 left, 1 right.
    pub hand: usize,
    /// Amplitude, 0..1.
    pub amplitude: f32,
    /// Duration in milliseconds.
    pub millis: u32,
}

/// A message for the user, shown in the headset (and written to the log by
/// whoever raised it).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Notice {
    /// The text (short: it is drawn with a stroke font).
    pub text: String,
    /// Whether it reports a problem (drawn in red).
    pub warning: bool,
}

/// Receives each frame's input. `core::interact` plugs in here.
pub trait FrameSink {
    /// Called once per input frame while the session is running.
    fn frame(&mut self, frame: &InputFrame);
    /// Called on lifecycle changes (default: ignored).
    fn lifecycle(&mut self, _event: &LifecycleEvent) {}
    /// What to draw for the document and the tool (default: nothing; the
    /// headset then draws only `--model` and the aim rays).
    fn scene(&self) -> Option<&Scene> {
        None
    }
    /// Haptic pulses to send now (default: none).
    fn take_haptics(&mut self) -> Vec<Haptic> {
        Vec::new()
    }
    /// Messages to show in the headset now (default: none).
    fn notices(&self) -> Vec<Notice> {
        Vec::new()
    }
    /// What the input sanitizer accepted and dropped (default: unknown).
    fn input_stats(&self) -> Option<SanitizerStats> {
        None
    }
    /// Called after each delivered frame in a paced run, before the pace
    /// is acknowledged, and once at the end of a run, before the input
    /// counts are read: wait for anything the frames started (default:
    /// nothing to wait for).
    fn settle(&mut self) {}
    /// Op-log length and command count, for pace acknowledgements.
    fn progress(&self) -> (u64, u64) {
        (0, 0)
    }
}

/// A sink that keeps every frame (tests, recording).
#[derive(Debug, Default)]
pub struct CollectSink {
    /// Frames received.
    pub frames: Vec<InputFrame>,
    /// Lifecycle events received.
    pub events: Vec<LifecycleEvent>,
}

impl FrameSink for CollectSink {
    fn frame(&mut self, frame: &InputFrame) {
        self.frames.push(frame.clone());
    }
    fn lifecycle(&mut self, event: &LifecycleEvent) {
        self.events.push(event.clone());
    }
}
