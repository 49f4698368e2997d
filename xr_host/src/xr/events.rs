//! Draining the event queue and applying the spec's lifecycle reactions;
//! used by the one frame loop ([`super::frame_loop`]).

use openxr as xr;

use super::input::{FrameSink, LifecycleEvent};
use super::lifecycle::{reaction, Beginnable, Phase, Reaction};
use super::{classify, Failure, RunReport, XrHostError};

/// How a session ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SessionEnd {
    /// EXITING (asked by the host or the runtime) or a limit was reached.
    Exit,
    /// LOSS_PENDING or ERROR_SESSION_LOST.
    Lost,
    /// Instance loss pending or ERROR_INSTANCE_LOST.
    InstanceLost,
}

/// Maps an OpenXR error: loss becomes a session end, anything else an error.
pub fn end_or_error(what: &'static str, err: xr::sys::Result) -> Result<SessionEnd, XrHostError> {
    match classify(err) {
        Failure::SessionLost => Ok(SessionEnd::Lost),
        Failure::InstanceLost => Ok(SessionEnd::InstanceLost),
        Failure::Other => Err(XrHostError::call(what, err)),
    }
}

/// The per-session lifecycle bookkeeping.
pub struct Lifecycle<S> {
    /// The session in its phase (None only transiently).
    pub phase: Option<Phase<S>>,
    /// The last state delivered.
    pub state: xr::SessionState,
    /// Whether the host called xrRequestExitSession.
    pub exit_requested: bool,
    /// An XrEventDataInteractionProfileChanged arrived (re-query the
    /// bound profiles).
    pub profile_changed: bool,
}

impl<S: Beginnable> Lifecycle<S> {
    /// A freshly created session.
    pub fn new(session: S) -> Self {
        Self {
            phase: Some(Phase::Idle(super::lifecycle::Idle::new(session))),
            state: xr::SessionState::IDLE,
            exit_requested: false,
            profile_changed: false,
        }
    }

    /// Polls every queued event and reacts as the spec says. Returns
    /// `Ok(Some(end))` when the session is over.
    pub fn drain(
        &mut self,
        instance: &xr::Instance,
        buf: &mut xr::EventDataBuffer,
        report: &mut RunReport,
        sink: &mut dyn FrameSink,
    ) -> Result<Option<SessionEnd>, XrHostError> {
        loop {
            let ev = match instance.poll_event(buf) {
                Ok(Some(ev)) => ev,
                Ok(None) => return Ok(None),
                Err(e) => return end_or_error("xrPollEvent", e).map(Some),
            };
            match ev {
                xr::Event::SessionStateChanged(e) => {
                    let state = e.state();
                    self.state = state;
                    report.states.push(format!("{state:?}"));
                    sink.lifecycle(&LifecycleEvent::State(format!("{state:?}")));
                    if state == xr::SessionState::FOCUSED {
                        report.reached_focused = true;
                    }
                    match reaction(state) {
                        Reaction::Begin => match self.phase.take() {
                            Some(Phase::Idle(idle)) => match idle.begin() {
                                Ok(r) => self.phase = Some(Phase::Running(r)),
                                Err((idle, err)) => {
                                    self.phase = Some(Phase::Idle(idle));
                                    return end_or_error("xrBeginSession", err).map(Some);
                                }
                            },
                            other => self.phase = other,
                        },
                        Reaction::End => match self.phase.take() {
                            Some(Phase::Running(r)) => {
                                let (idle, err) = r.end();
                                self.phase = Some(Phase::Idle(idle));
                                if let Some(err) = err {
                                    return end_or_error("xrEndSession", err).map(Some);
                                }
                            }
                            other => self.phase = other,
                        },
                        Reaction::Exit => {
                            report.exit_reason =
                                match (self.exit_requested, report.exit_reason.is_empty()) {
                                    (true, true) => "exit requested by the host".into(),
                                    (true, false) => format!(
                                        "exit requested by the host: {}",
                                        report.exit_reason
                                    ),
                                    (false, _) => "exit requested by the runtime".into(),
                                };
                            return Ok(Some(SessionEnd::Exit));
                        }
                        Reaction::SessionLost => return Ok(Some(SessionEnd::Lost)),
                        Reaction::None => {}
                    }
                }
                xr::Event::InstanceLossPending(_) => return Ok(Some(SessionEnd::InstanceLost)),
                xr::Event::InteractionProfileChanged(_) => self.profile_changed = true,
                xr::Event::EventsLost(e) => report.events_lost += u64::from(e.lost_event_count()),
                _ => {}
            }
        }
    }
}
