//! What a run is given ([`RunConfig`]) and what it reports
//! ([`RunReport`]: frames, timings, input, notices).

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use super::instance::RuntimeInfo;
use super::spaces::SpaceReport;
use shapewright::interact::SanitizerStats;

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
    /// Give up if a session is not READY this long after creation (and
    /// if the runtime does not reach EXITING this long after an exit
    /// request).
    pub stall_timeout: Duration,
    /// Set (by a signal handler) to ask the session to end: the loop calls
    /// xrRequestExitSession and runs the normal STOPPING/EXITING path.
    pub stop: Option<Arc<AtomicBool>>,
    /// Pace the run by a client listening at this loopback address ([`pace`](super::pace)).
    pub pace: Option<std::net::SocketAddr>,
    /// Behave as an OpenXR 1.0 application (see [`instance`](super::instance)).
    pub openxr_1_0: bool,
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
            stop: None,
            pace: None,
            openxr_1_0: false,
        }
    }
}

/// What happened during a run.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct RunReport {
    /// What the runtime and its system are.
    pub runtime: RuntimeInfo,
    /// The base space used and what was offered.
    pub spaces: SpaceReport,
    /// The interaction profile bound to the left and right hand (after the
    /// first sync; None: nothing bound).
    pub profiles_bound: [Option<String>; 2],
    /// Whether joints were reported for each hand, and their source
    /// (`optical`, `controller`, `unknown`).
    pub hands_tracked: [Option<String>; 2],
    /// Whether any controller or tracked hand ever reported input.
    pub input_device: bool,
    /// Input frames handed to the sink.
    pub frames: u64,
    /// Input frames per second of input time (the runtime's clock, or the
    /// trace's in a paced run).
    pub input_hz: f64,
    /// Frames submitted (headset: xrEndFrame; headless: ticks).
    pub display_frames: u64,
    /// Display frames per second while the session ran (wall clock).
    pub display_hz: f64,
    /// Poses dropped by the sanitizer (untracked or unusable).
    pub poses_dropped: u64,
    /// Hand joints marked valid but unusable.
    pub joints_dropped: u64,
    /// The input sanitizer's counts.
    pub input: Option<SanitizerStats>,
    /// Paced runs: steps taken, and display frames that waited for the
    /// runtime to deliver a step's packet.
    pub pace_steps: u64,
    /// See [`RunReport::pace_steps`].
    pub pace_waits: u64,
    /// Haptic pulses sent.
    pub haptics_sent: u64,
    /// Things the user should know (no input device, ...).
    pub notes: Vec<String>,
    /// What the runtime refused and what the host used instead (a base
    /// space lower on the chain, no hand trackers, a profile's bindings
    /// skipped), in order; each was also logged.
    pub fallbacks: Vec<String>,
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
    /// Interaction profiles the runtime accepted suggested bindings for.
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
