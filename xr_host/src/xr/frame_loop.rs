//! The one frame loop both modes run (issue 15 item 4). The graphics part
//! is the only difference, behind [`Graphics`]: the headless mode
//! ([`super::headless`]) paces itself with a sleep and takes time from
//! `xrConvertTimespecTimeToTimeKHR`; the headset ([`super::headset`]) runs
//! xrWaitFrame / xrBeginFrame / xrEndFrame and draws.
//!
//! Per the spec (OpenXR 1.1 §10.3): events are polled every tick; READY
//! begins, STOPPING ends, EXITING stops, LOSS_PENDING (or
//! ERROR_SESSION_LOST) destroys the session and recreates it, instance loss
//! destroys the instance and retries creating it. A stop request (a
//! signal, a frame or time limit, the end of a paced trace) calls
//! xrRequestExitSession and the loop keeps running until the runtime walks
//! the session through STOPPING to EXITING, so the normal end path runs.

use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use openxr as xr;
use shapewright::interact::InputFrame;

use super::actions::{Actions, ReadInfo, SessionInput, HAND_PATHS};
use super::events::{end_or_error, Lifecycle, SessionEnd};
use super::input::{FrameSink, LifecycleEvent, Notice};
use super::instance::{create_instance, InstanceCaps};
use super::lifecycle::{reads_input, Phase};
use super::pace::{angle_tag, Pacer};
use super::spaces::{Fallback, SpaceReport};
use super::{classify, Failure, RunConfig, RunReport, XrHostError};

/// What a tick of the graphics side needs to know about the frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameTime {
    /// The time input is read at (the predicted display time, or now).
    pub time: xr::Time,
    /// Whether the runtime wants this frame rendered.
    pub should_render: bool,
}

/// An error inside a tick: an OpenXR call (which may mean loss) or
/// anything else.
pub enum TickError {
    /// An OpenXR call failed.
    Xr(&'static str, xr::sys::Result),
    /// Something else failed.
    Host(XrHostError),
}

impl From<XrHostError> for TickError {
    fn from(e: XrHostError) -> Self {
        TickError::Host(e)
    }
}

/// What the graphics side draws besides the sink's scene.
pub struct Overlay<'a> {
    /// The frame's input (for aim rays without a scene).
    pub frame: Option<&'a InputFrame>,
    /// Messages to show.
    pub notices: &'a [Notice],
}

/// The part of a mode that differs: graphics binding, frame calls, drawing.
pub trait Graphics {
    /// The openxr crate's graphics type.
    type Api: xr::Graphics;
    /// Whether the instance is created for `XR_MND_headless`.
    const HEADLESS: bool;
    /// After the instance exists (Vulkan: the device through the runtime).
    fn instance_created(&mut self, caps: &InstanceCaps) -> Result<(), XrHostError>;
    /// Creates a session (keeping any frame-protocol objects).
    fn create_session(&mut self, caps: &InstanceCaps) -> xr::Result<xr::Session<Self::Api>>;
    /// After the session exists (Vulkan: swapchains, uploads).
    fn session_created(
        &mut self,
        caps: &InstanceCaps,
        session: &xr::Session<Self::Api>,
    ) -> Result<(), TickError>;
    /// Waits for the next frame of a running session.
    fn wait_frame(&mut self, caps: &InstanceCaps, cfg: &RunConfig) -> Result<FrameTime, TickError>;
    /// Finishes the frame begun by [`Graphics::wait_frame`]: draws and
    /// submits it (headset) or nothing (headless).
    fn end_frame(
        &mut self,
        session: &xr::Session<Self::Api>,
        input: &SessionInput,
        ft: FrameTime,
        sink: &dyn FrameSink,
        overlay: &Overlay<'_>,
    ) -> Result<(), TickError>;
    /// Frames submitted so far.
    fn frames_submitted(&self) -> u64;
    /// Called while the session exists but is not running.
    fn idle(&mut self, cfg: &RunConfig);
    /// The session is over: drop what belongs to it.
    fn session_ended(&mut self);
    /// The instance is over: drop what belongs to it.
    fn instance_ended(&mut self);
}

/// Runs `gfx`'s mode until the configured limits, a stop request, EXITING
/// from the runtime, or retries are exhausted.
pub fn run<Gx: Graphics>(
    cfg: &RunConfig,
    gfx: &mut Gx,
    sink: &mut dyn FrameSink,
) -> Result<RunReport, XrHostError> {
    let start = Instant::now();
    let mut report = RunReport::default();
    let mut pacer = match &cfg.pace {
        Some(a) => Some(Pacer::connect(*a).map_err(|e| XrHostError::GaveUp(e.to_string()))?),
        None => None,
    };
    let mut failures = 0u32;
    let result = loop {
        let caps = match create_instance(Gx::HEADLESS, cfg) {
            Ok(c) => c,
            // A missing runtime at start fails fast; after a loss the runtime
            // may need a while to come back, so creation is retried.
            Err(e)
                if e.is_retryable()
                    && report.instances_created > 0
                    && failures < cfg.max_instance_retries =>
            {
                failures += 1;
                report.instance_retries += 1;
                std::thread::sleep(cfg.retry_delay);
                continue;
            }
            Err(e) => break Err(e),
        };
        report.instances_created += 1;
        report.runtime = caps.info.clone();
        if let Err(e) = gfx.instance_created(&caps) {
            break Err(e);
        }
        let end = run_instance(&caps, cfg, gfx, sink, &mut report, pacer.as_mut(), start);
        gfx.instance_ended();
        match end {
            Ok(SessionEnd::InstanceLost) => {
                report.instance_losses += 1;
                sink.lifecycle(&LifecycleEvent::InstanceLost);
                drop(caps);
                if report.instance_losses > cfg.max_instance_retries {
                    break Err(XrHostError::GaveUp(
                        "the instance was lost too often".into(),
                    ));
                }
                std::thread::sleep(cfg.retry_delay);
            }
            Ok(_) => break Ok(()),
            Err(e) => break Err(e),
        }
    };
    note_input_stats(&mut report, sink);
    if let Some(p) = &pacer {
        report.pace_steps = p.steps;
        report.pace_waits = p.waits;
    }
    report.display_frames = gfx.frames_submitted();
    result.map(|()| report)
}

/// Reads the sink's input counts into `report` once every frame the sink
/// received has been stepped: frames held for a commit still running are
/// stepped first ([`FrameSink::settle`]). Read before that, a run that
/// ended during a slow commit counted the poses of its held frames as
/// never dropped (a loaded machine's `testrt` run reported 0 of 60 NaN
/// and lost poses, 2026-12-01).
pub fn note_input_stats(report: &mut RunReport, sink: &mut dyn FrameSink) {
    sink.settle();
    report.input = sink.input_stats();
    if let Some(s) = &report.input {
        report.poses_dropped = s.poses_untracked + s.poses_rejected;
        report.joints_dropped = s.joints_rejected;
    }
}

fn run_instance<Gx: Graphics>(
    caps: &InstanceCaps,
    cfg: &RunConfig,
    gfx: &mut Gx,
    sink: &mut dyn FrameSink,
    report: &mut RunReport,
    mut pacer: Option<&mut Pacer>,
    start: Instant,
) -> Result<SessionEnd, XrHostError> {
    let actions = match Actions::new(&caps.instance, caps.api, &caps.enabled) {
        Ok(a) => a,
        Err(e) => {
            return match classify(e) {
                Failure::InstanceLost => Ok(SessionEnd::InstanceLost),
                _ => Err(XrHostError::call("creating actions", e)),
            }
        }
    };
    report.profiles = actions.accepted_profiles.clone();
    note_fallbacks(report, actions.fallbacks.iter().cloned());
    let mut recreations = 0u32;
    loop {
        let session = match gfx.create_session(caps) {
            Ok(s) => s,
            Err(e) => return end_or_error("xrCreateSession", e),
        };
        report.sessions_created += 1;
        sink.lifecycle(&LifecycleEvent::SessionCreated);
        let end = run_session(
            session,
            caps,
            &actions,
            cfg,
            gfx,
            sink,
            report,
            pacer.as_deref_mut(),
            start,
        );
        gfx.session_ended();
        match end? {
            SessionEnd::Lost => {
                report.session_losses += 1;
                sink.lifecycle(&LifecycleEvent::SessionLost);
                recreations += 1;
                if !cfg.recreate_lost_sessions || recreations > cfg.max_session_recreations {
                    report.exit_reason = "session lost".into();
                    return Ok(SessionEnd::Exit);
                }
            }
            other => return Ok(other),
        }
    }
}

/// Why the host wants to stop, if it does.
fn stop_reason(
    cfg: &RunConfig,
    report: &RunReport,
    pacer: Option<&Pacer>,
    start: Instant,
) -> Option<String> {
    if cfg.stop.as_ref().is_some_and(|s| s.load(Ordering::SeqCst)) {
        return Some("a signal asked the host to stop".into());
    }
    if cfg.max_frames.is_some_and(|n| report.frames >= n) {
        return Some("the frame limit was reached".into());
    }
    if cfg.max_duration.is_some_and(|d| start.elapsed() >= d) {
        return Some("the time limit was reached".into());
    }
    if pacer.is_some_and(Pacer::ended) {
        return Some("the paced trace ended".into());
    }
    None
}

/// Frames in FOCUSED without any controller or hand before the host says
/// there is no input device.
const NO_INPUT_FRAMES: u64 = 30;

#[allow(clippy::too_many_arguments)]
fn run_session<Gx: Graphics>(
    session: xr::Session<Gx::Api>,
    caps: &InstanceCaps,
    actions: &Actions,
    cfg: &RunConfig,
    gfx: &mut Gx,
    sink: &mut dyn FrameSink,
    report: &mut RunReport,
    mut pacer: Option<&mut Pacer>,
    start: Instant,
) -> Result<SessionEnd, XrHostError> {
    let mut input = match SessionInput::new(&session, actions, caps) {
        Ok(i) => i,
        Err(e) => return end_or_error("creating spaces and hand trackers", e),
    };
    note_fallbacks(report, input.take_fallbacks());
    report.spaces.offered = input.offered_spaces.clone();
    match gfx.session_created(caps, &session) {
        Ok(()) => {}
        Err(TickError::Xr(call, r)) => return end_or_error(call, r),
        Err(TickError::Host(e)) => return Err(e),
    }
    let mut life = Lifecycle::new(session);
    let mut buf = xr::EventDataBuffer::new();
    let session_start = Instant::now();
    let mut stop_asked_at: Option<Instant> = None;
    let mut profiles_dirty = true;
    let mut focused_frames = 0u64;
    let mut no_input_said = false;
    let mut first_time: Option<f64> = None;
    let mut running_since: Option<(Instant, u64)> = None;
    // Unwraps `$e`; a lost session or instance leaves the tick loop with
    // that outcome, any other error ends the run with a typed error.
    macro_rules! tick_try {
        ($lt:lifetime, $e:expr) => {
            match $e {
                Ok(v) => v,
                Err(TickError::Xr(what, err)) => break $lt end_or_error(what, err)?,
                Err(TickError::Host(e)) => return Err(e),
            }
        };
    }
    macro_rules! xr_try {
        ($lt:lifetime, $what:expr, $e:expr) => {
            tick_try!($lt, $e.map_err(|r| TickError::Xr($what, r)))
        };
    }
    let end = 'tick: loop {
        // 1. Drain the event queue, reacting to state changes.
        let drained = life.drain(&caps.instance, &mut buf, report, sink)?;
        if life.profile_changed {
            profiles_dirty = true;
            life.profile_changed = false;
        }
        if let Some(end) = drained {
            break end;
        }
        // 2. Stop when asked: request exit while running, then keep going
        // until the runtime reaches STOPPING/EXITING.
        if !life.exit_requested {
            let asked = ask_to_stop(&mut life, cfg, report, pacer.as_deref(), start, sink);
            match tick_try!('tick, asked) {
                StopAsk::No => {}
                StopAsk::Asked => stop_asked_at = Some(Instant::now()),
                StopAsk::NeverRan => break SessionEnd::Exit,
            }
        }
        check_stalls(cfg, report, life.state, session_start, stop_asked_at)?;
        let Some(Phase::Running(running)) = &life.phase else {
            gfx.idle(cfg);
            continue;
        };
        // 3. One frame: wait, read input, step, draw.
        let ft = tick_try!('tick, gfx.wait_frame(caps, cfg));
        let session = running.session();
        let based = xr_try!('tick, "locating the base space", input.establish(session, ft.time));
        note_fallbacks(report, input.take_fallbacks());
        if based && report.spaces.base.is_empty() {
            note_base_space(report, &input);
        }
        let mut delivered = None;
        // No input after an exit request: a limit means exactly that many
        // frames, and a stop means no new edits while the session winds down.
        if based && reads_input(life.state) && !life.exit_requested {
            let t0 = Instant::now();
            // In a paced run, the packet's tag is read before anything else.
            let tag = match pacer.as_deref_mut() {
                Some(p) => tick_try!('tick, paced_tag(p, session, &input, ft.time)),
                None => None,
            };
            let time_s = ft.time.as_nanos() as f64 * 1e-9;
            let (mut frame, info) =
                xr_try!('tick, "reading input", input.read(running, actions, ft.time, time_s));
            let step_time = match pacer.as_deref_mut() {
                Some(p) => p.admit(tag),
                None => Some(time_s),
            };
            if let Some(t) = step_time {
                frame.time = t;
                let submitted = gfx.frames_submitted();
                let pacer = pacer.as_deref_mut();
                deliver(&frame, t0, &mut first_time, report, sink, pacer, submitted)?;
            }
            note_devices(report, &frame, &info);
            if profiles_dirty {
                let bound = xr_try!('tick, "xrGetCurrentInteractionProfile", actions.bound_profiles(session));
                profiles_dirty = false;
                note_profiles(report, sink, bound);
            }
            if life.state == xr::SessionState::FOCUSED {
                focused_frames += 1;
            }
            if focused_frames >= NO_INPUT_FRAMES && !report.input_device && !no_input_said {
                no_input_said = true;
                eprintln!(
                    "shapewright-xr: no input device: the system reports no controller and no tracked hand, so no tool can be driven"
                );
            }
            delivered = Some(frame);
        }
        // 4. Haptics the sink asked for.
        for pulse in sink.take_haptics() {
            xr_try!('tick, "xrApplyHapticFeedback", actions.vibrate(session, &pulse));
            report.haptics_sent += 1;
        }
        // 5. Draw and submit.
        let notices = with_no_input_notice(sink.notices(), no_input_said);
        let overlay = Overlay {
            frame: delivered.as_ref(),
            notices: &notices,
        };
        tick_try!('tick, gfx.end_frame(session, &input, ft, sink, &overlay));
        note_display_rate(report, &mut running_since, gfx.frames_submitted());
    };
    if report.reached_focused && report.frames > 0 && !report.input_device {
        report
            .notes
            .push("no input device: no controller and no tracked hand".into());
    }
    // Spaces and trackers go before the session.
    drop(input);
    drop(life);
    Ok(end)
}

/// What [`ask_to_stop`] did.
enum StopAsk {
    /// Nothing asks the host to stop.
    No,
    /// Exit was requested; the loop runs on until STOPPING/EXITING.
    Asked,
    /// A stop came before the session ran: the run ends here.
    NeverRan,
}

/// Step 2 of the tick: when a signal or a limit says stop, requests exit
/// from a running session, or ends one that never ran.
fn ask_to_stop<G: xr::Graphics>(
    life: &mut Lifecycle<xr::Session<G>>,
    cfg: &RunConfig,
    report: &mut RunReport,
    pacer: Option<&Pacer>,
    start: Instant,
    sink: &mut dyn FrameSink,
) -> Result<StopAsk, TickError> {
    let Some(why) = stop_reason(cfg, report, pacer, start) else {
        return Ok(StopAsk::No);
    };
    match &life.phase {
        Some(Phase::Running(r)) => {
            r.session()
                .request_exit()
                .map_err(|e| TickError::Xr("xrRequestExitSession", e))?;
            life.exit_requested = true;
            sink.lifecycle(&LifecycleEvent::ExitRequested(why.clone()));
            report.exit_reason = why;
            Ok(StopAsk::Asked)
        }
        _ => {
            report.exit_reason = format!("{why} before the session ran");
            Ok(StopAsk::NeverRan)
        }
    }
}

/// Gives up on a runtime that never makes the session READY, or never
/// reaches EXITING after an exit request, within the stall timeout.
fn check_stalls(
    cfg: &RunConfig,
    report: &RunReport,
    state: xr::SessionState,
    session_start: Instant,
    stop_asked_at: Option<Instant>,
) -> Result<(), XrHostError> {
    if session_start.elapsed() > cfg.stall_timeout
        && !report.reached_focused
        && state == xr::SessionState::IDLE
    {
        return Err(XrHostError::GaveUp(format!(
            "the session did not become READY within {:?}",
            cfg.stall_timeout
        )));
    }
    if stop_asked_at.is_some_and(|t| t.elapsed() > cfg.stall_timeout) {
        return Err(XrHostError::GaveUp(
            "the runtime did not reach EXITING after xrRequestExitSession".into(),
        ));
    }
    Ok(())
}

/// Reports the base space the input settled on (once it has one).
fn note_base_space(report: &mut RunReport, input: &SessionInput) {
    if let Some((kind, h)) = input.base_kind {
        report.spaces = SpaceReport {
            offered: input.offered_spaces.clone(),
            base: serde_json::to_value(kind)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default(),
            floor_offset_m: h,
        };
    }
}

/// In a paced run, polls the pacer and reads the packet's tag, which the
/// driver encodes in the first view's upward field-of-view angle.
fn paced_tag<G: xr::Graphics>(
    pacer: &mut Pacer,
    session: &xr::Session<G>,
    input: &SessionInput,
    time: xr::Time,
) -> Result<Option<u32>, TickError> {
    if let Err(e) = pacer.poll() {
        return Err(XrHostError::GaveUp(e.to_string()).into());
    }
    let (_, views) = session
        .locate_views(
            xr::ViewConfigurationType::PRIMARY_STEREO,
            time,
            input.view(),
        )
        .map_err(|e| TickError::Xr("xrLocateViews", e))?;
    Ok(views.first().and_then(|v| angle_tag(v.fov.angle_up)))
}

/// Hands the sink one frame of input (stamped with its step time) and
/// counts it; in a paced run, lets the sink settle and acknowledges the
/// packet with the progress it made.
fn deliver(
    frame: &InputFrame,
    read_at: Instant,
    first_time: &mut Option<f64>,
    report: &mut RunReport,
    sink: &mut dyn FrameSink,
    pacer: Option<&mut Pacer>,
    frames_submitted: u64,
) -> Result<(), XrHostError> {
    let t = frame.time;
    sink.frame(frame);
    report
        .frame_cpu_us
        .push(read_at.elapsed().as_secs_f64() * 1e6);
    report.frames += 1;
    let t0 = *first_time.get_or_insert(t);
    if t > t0 {
        report.input_hz = (report.frames - 1) as f64 / (t - t0);
    }
    if let Some(p) = pacer {
        sink.settle();
        let (ops, commands) = sink.progress();
        p.ack(frames_submitted, ops, commands)
            .map_err(|e| XrHostError::GaveUp(e.to_string()))?;
    }
    Ok(())
}

/// The sink's notices, and a warning when no device can drive a tool.
fn with_no_input_notice(mut notices: Vec<Notice>, no_input: bool) -> Vec<Notice> {
    if no_input {
        notices.push(Notice {
            text: "NO CONTROLLER OR HAND: NOTHING CAN DRIVE THE TOOL".into(),
            warning: true,
        });
    }
    notices
}

/// Reports the rate frames were submitted at since the session first ran.
fn note_display_rate(report: &mut RunReport, since: &mut Option<(Instant, u64)>, submitted: u64) {
    let (t0, n0) = *since.get_or_insert((Instant::now(), submitted));
    let secs = t0.elapsed().as_secs_f64();
    if secs > 0.0 {
        report.display_hz = (submitted - n0) as f64 / secs;
    }
}

/// Reports which hands are tracked and whether any device gives input.
fn note_devices(report: &mut RunReport, frame: &InputFrame, info: &ReadInfo) {
    for (h, s) in info.hands.iter().enumerate() {
        if let Some(s) = s {
            report.hands_tracked[h] = Some(format!("{s:?}").to_lowercase());
        }
    }
    if frame.controllers.iter().any(Option::is_some) || frame.hands.iter().any(Option::is_some) {
        report.input_device = true;
    }
}

/// Tells the sink about each hand whose bound interaction profile changed
/// (every hand on the first frame) and reports the bound profiles.
fn note_profiles(report: &mut RunReport, sink: &mut dyn FrameSink, bound: [Option<String>; 2]) {
    for (h, p) in bound.iter().enumerate() {
        if report.profiles_bound[h] != *p || report.frames <= 1 {
            sink.lifecycle(&LifecycleEvent::ProfileBound {
                hand: HAND_PATHS[h].into(),
                profile: p.clone(),
            });
        }
    }
    report.profiles_bound = bound;
}

/// Logs each rung given up and adds it to the report.
fn note_fallbacks(report: &mut RunReport, fallbacks: impl IntoIterator<Item = Fallback>) {
    for f in fallbacks {
        eprintln!("shapewright-xr: fallback: {f}");
        report.fallbacks.push(f.0);
    }
}

/// Sleeps until `next`, then moves it one `period` on (or to now when the
/// loop fell behind).
pub fn sleep_until(next: &mut Instant, period: Duration) {
    let now = Instant::now();
    if *next > now {
        std::thread::sleep(*next - now);
    } else {
        *next = now;
    }
    *next += period;
}
