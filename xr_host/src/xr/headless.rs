//! `run --headless`: an `XR_MND_headless` session, input only.
//!
//! The loop never calls xrWaitFrame/xrBeginFrame (a headless runtime may
//! refuse them); it paces itself with a sleep and takes the time from
//! `xrConvertTimespecTimeToTimeKHR`. Lifecycle per the spec: events are
//! polled every tick; READY begins, STOPPING ends, EXITING stops,
//! LOSS_PENDING (or ERROR_SESSION_LOST) destroys the session and
//! recreates it, instance loss (XrEventDataInstanceLossPending or
//! ERROR_INSTANCE_LOST) destroys the instance and retries creating it.

use std::time::{Duration, Instant};

use openxr as xr;

use super::actions::{Actions, DropCounts, SessionInput};
use super::events::{end_or_error, Lifecycle, SessionEnd};
use super::input::{FrameSink, LifecycleEvent};
use super::lifecycle::{reads_input, Phase};
use super::{classify, create_instance, Failure, InstanceCaps, RunConfig, RunReport, XrHostError};
use crate::gfx::xr_bridge::create_headless_session;

enum InstanceEnd {
    Exit,
    Lost,
}

/// Runs the headless input loop until the configured frame count or time
/// is reached (then requests exit and waits for EXITING), the runtime
/// exits the session, or retries are exhausted.
pub fn run_headless(cfg: &RunConfig, sink: &mut dyn FrameSink) -> Result<RunReport, XrHostError> {
    let start = Instant::now();
    let mut report = RunReport::default();
    let mut failures = 0u32;
    loop {
        let caps = match create_instance(cfg, true) {
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
            Err(e) => return Err(e),
        };
        report.instances_created += 1;
        match run_instance(&caps, cfg, sink, &mut report, start)? {
            InstanceEnd::Exit => return Ok(report),
            InstanceEnd::Lost => {
                report.instance_losses += 1;
                sink.lifecycle(&LifecycleEvent::InstanceLost);
                drop(caps);
                if report.instance_losses > cfg.max_instance_retries {
                    return Err(XrHostError::GaveUp(
                        "the instance was lost too often".into(),
                    ));
                }
                std::thread::sleep(cfg.retry_delay);
            }
        }
    }
}

fn run_instance(
    caps: &InstanceCaps,
    cfg: &RunConfig,
    sink: &mut dyn FrameSink,
    report: &mut RunReport,
    start: Instant,
) -> Result<InstanceEnd, XrHostError> {
    let actions = match Actions::new(&caps.instance, &caps.enabled) {
        Ok(a) => a,
        Err(e) => {
            return match classify(e) {
                Failure::InstanceLost => Ok(InstanceEnd::Lost),
                _ => Err(XrHostError::call("creating actions", e)),
            }
        }
    };
    report.profiles = actions
        .accepted_profiles
        .iter()
        .map(|s| s.to_string())
        .collect();
    let mut recreations = 0u32;
    loop {
        let session = match create_headless_session(&caps.instance, caps.system) {
            Ok(s) => s,
            Err(e) => {
                return match classify(e) {
                    Failure::InstanceLost => Ok(InstanceEnd::Lost),
                    _ => Err(XrHostError::call("xrCreateSession", e)),
                }
            }
        };
        report.sessions_created += 1;
        sink.lifecycle(&LifecycleEvent::SessionCreated);
        let end = run_session(session, caps, &actions, cfg, sink, report, start)?;
        match end {
            SessionEnd::Exit => return Ok(InstanceEnd::Exit),
            SessionEnd::InstanceLost => return Ok(InstanceEnd::Lost),
            SessionEnd::Lost => {
                report.session_losses += 1;
                sink.lifecycle(&LifecycleEvent::SessionLost);
                recreations += 1;
                if !cfg.recreate_lost_sessions || recreations > cfg.max_session_recreations {
                    report.exit_reason = "session lost".into();
                    return Ok(InstanceEnd::Exit);
                }
            }
        }
    }
}

fn run_session(
    session: xr::Session<xr::Headless>,
    caps: &InstanceCaps,
    actions: &Actions,
    cfg: &RunConfig,
    sink: &mut dyn FrameSink,
    report: &mut RunReport,
    start: Instant,
) -> Result<SessionEnd, XrHostError> {
    let input = match SessionInput::new(&session, actions, caps.hand_tracking) {
        Ok(i) => i,
        Err(e) => {
            return match classify(e) {
                Failure::SessionLost => Ok(SessionEnd::Lost),
                Failure::InstanceLost => Ok(SessionEnd::InstanceLost),
                Failure::Other => Err(XrHostError::call("creating spaces", e)),
            }
        }
    };
    let mut life = Lifecycle::new(session);
    let mut buf = xr::EventDataBuffer::new();
    let mut drops = DropCounts::default();
    let session_start = Instant::now();
    let mut next_tick = Instant::now();
    // Unwraps `$e`; a lost session or instance leaves the tick loop with
    // that outcome, any other error ends the run with a typed error.
    macro_rules! xr_try {
        ($lt:lifetime, $what:expr, $e:expr) => {
            match $e {
                Ok(v) => v,
                Err(err) => break $lt end_or_error($what, err)?,
            }
        };
    }
    let end = 'tick: loop {
        // 1. Drain the event queue, reacting to state changes.
        if let Some(end) = life.drain(&caps.instance, &mut buf, report, sink)? {
            break end;
        }
        // 2. Read input while running.
        if let Some(Phase::Running(running)) = &life.phase {
            if reads_input(life.state) {
                let t0 = Instant::now();
                let time = xr_try!('tick, "xrConvertTimespecTimeToTimeKHR", caps.instance.now());
                let frame = xr_try!(
                    'tick,
                    "reading input",
                    input.read(running, actions, time, report.frames, &mut drops)
                );
                sink.frame(&frame);
                report.frame_cpu_us.push(t0.elapsed().as_secs_f64() * 1e6);
                report.frames += 1;
            }
        }
        // 3. Stop when asked: request exit while running, then wait for
        // STOPPING/EXITING through the event queue.
        let done = cfg.max_frames.is_some_and(|n| report.frames >= n)
            || cfg.max_duration.is_some_and(|d| start.elapsed() >= d);
        if done && !life.exit_requested {
            match &life.phase {
                Some(Phase::Running(r)) => {
                    xr_try!('tick, "xrRequestExitSession", r.session().request_exit());
                    life.exit_requested = true;
                }
                _ => {
                    report.exit_reason = "limit reached before the session ran".into();
                    break SessionEnd::Exit;
                }
            }
        }
        if session_start.elapsed() > cfg.stall_timeout
            && !report.reached_focused
            && life.state == xr::SessionState::IDLE
        {
            return Err(XrHostError::GaveUp(format!(
                "the session did not become READY within {:?}",
                cfg.stall_timeout
            )));
        }
        if life.exit_requested
            && start.elapsed()
                > cfg
                    .max_duration
                    .unwrap_or(Duration::MAX)
                    .saturating_add(cfg.stall_timeout)
        {
            return Err(XrHostError::GaveUp(
                "the runtime did not reach EXITING after xrRequestExitSession".into(),
            ));
        }
        next_tick += cfg.frame_period;
        let now = Instant::now();
        if next_tick > now {
            std::thread::sleep(next_tick - now);
        } else {
            next_tick = now;
        }
    };
    report.poses_dropped += drops.poses;
    report.joints_dropped += drops.joints;
    // Spaces and trackers go before the session (field order of drops).
    drop(input);
    drop(life);
    Ok(end)
}
