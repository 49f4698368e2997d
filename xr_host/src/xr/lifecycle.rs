//! The session lifecycle as types (OpenXR 1.0 §9.3): a session is either
//! [`Idle`] (created, or ended) or [`Running`] (begun). Only an `Idle`
//! session can be begun (on READY), only a `Running` one ended (on
//! STOPPING), and input can only be read through `Running`, so calling
//! xrBeginSession twice or reading input from a stopped session does not
//! compile.

use openxr as xr;

/// What the host must do after a session state change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reaction {
    /// Nothing to do (SYNCHRONIZED, VISIBLE, FOCUSED, IDLE).
    None,
    /// READY: call xrBeginSession.
    Begin,
    /// STOPPING: call xrEndSession.
    End,
    /// EXITING: destroy the session and stop.
    Exit,
    /// LOSS_PENDING: destroy the session; recreate it or stop.
    SessionLost,
}

/// The spec's reaction to entering `state`.
pub fn reaction(state: xr::SessionState) -> Reaction {
    match state {
        xr::SessionState::READY => Reaction::Begin,
        xr::SessionState::STOPPING => Reaction::End,
        xr::SessionState::EXITING => Reaction::Exit,
        xr::SessionState::LOSS_PENDING => Reaction::SessionLost,
        _ => Reaction::None,
    }
}

/// Whether input may be read in `state` (the session is running and
/// synchronized; actions only update while FOCUSED).
pub fn reads_input(state: xr::SessionState) -> bool {
    matches!(
        state,
        xr::SessionState::SYNCHRONIZED | xr::SessionState::VISIBLE | xr::SessionState::FOCUSED
    )
}

/// A session that can be begun and ended.
pub trait Beginnable {
    /// xrBeginSession.
    fn begin_session(&self) -> xr::Result<()>;
    /// xrEndSession.
    fn end_session(&self) -> xr::Result<()>;
}

impl<G: xr::Graphics> Beginnable for xr::Session<G> {
    fn begin_session(&self) -> xr::Result<()> {
        self.begin(xr::ViewConfigurationType::PRIMARY_STEREO)
            .map(|_| ())
    }
    fn end_session(&self) -> xr::Result<()> {
        self.end().map(|_| ())
    }
}

/// A created session that is not running.
#[derive(Debug)]
pub struct Idle<S>(S);

/// A running session (between xrBeginSession and xrEndSession).
#[derive(Debug)]
pub struct Running<S>(S);

/// The two phases.
#[derive(Debug)]
pub enum Phase<S> {
    /// Not running.
    Idle(Idle<S>),
    /// Running.
    Running(Running<S>),
}

impl<S: Beginnable> Idle<S> {
    /// A freshly created session.
    pub fn new(session: S) -> Self {
        Self(session)
    }
    /// xrBeginSession; on failure the session stays idle.
    pub fn begin(self) -> Result<Running<S>, (Self, xr::sys::Result)> {
        match self.0.begin_session() {
            Ok(()) => Ok(Running(self.0)),
            Err(e) => Err((self, e)),
        }
    }
    /// The session.
    pub fn session(&self) -> &S {
        &self.0
    }
}

impl<S: Beginnable> Running<S> {
    /// xrEndSession; on failure the session is still handed back as idle
    /// (the runtime considers it ended or lost either way).
    pub fn end(self) -> (Idle<S>, Option<xr::sys::Result>) {
        let r = self.0.end_session().err();
        (Idle(self.0), r)
    }
    /// The session.
    pub fn session(&self) -> &S {
        &self.0
    }
}

impl<S> Phase<S> {
    /// The session in either phase.
    pub fn session(&self) -> &S {
        match self {
            Phase::Idle(i) => &i.0,
            Phase::Running(r) => &r.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    #[derive(Default)]
    struct Fake {
        begun: Cell<u32>,
        ended: Cell<u32>,
    }
    impl Beginnable for Fake {
        fn begin_session(&self) -> xr::Result<()> {
            self.begun.set(self.begun.get() + 1);
            Ok(())
        }
        fn end_session(&self) -> xr::Result<()> {
            self.ended.set(self.ended.get() + 1);
            Ok(())
        }
    }

    #[test]
    fn spec_reactions() {
        use xr::SessionState as S;
        assert_eq!(reaction(S::READY), Reaction::Begin);
        assert_eq!(reaction(S::STOPPING), Reaction::End);
        assert_eq!(reaction(S::EXITING), Reaction::Exit);
        assert_eq!(reaction(S::LOSS_PENDING), Reaction::SessionLost);
        for s in [S::IDLE, S::SYNCHRONIZED, S::VISIBLE, S::FOCUSED] {
            assert_eq!(reaction(s), Reaction::None);
        }
        assert!(reads_input(S::FOCUSED) && !reads_input(S::IDLE) && !reads_input(S::STOPPING));
    }

    #[test]
    fn begin_then_end_round_trips() {
        let idle = Idle::new(Fake::default());
        let running = idle.begin().map_err(|_| ()).unwrap();
        let (idle, err) = running.end();
        assert!(err.is_none());
        assert_eq!(idle.session().begun.get(), 1);
        assert_eq!(idle.session().ended.get(), 1);
    }
}
