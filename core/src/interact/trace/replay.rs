//! [`replay`]: a trace's frames through a fresh session and tool, the
//! commands they make applied to a new log ([`Replay`]).

use crate::doc::{LogError, OpLog, ScriptCommand};

use super::format::{Trace, TraceError};

/// The result of replaying a trace.
#[derive(Debug)]
pub struct Replay {
    /// Commands the session produced, in order (including any the log
    /// refused).
    pub commands: Vec<ScriptCommand>,
    /// The log after applying them.
    pub log: OpLog,
    /// Commands the log refused: (index into `commands`, why). A refused
    /// command changes nothing.
    pub rejected: Vec<(usize, LogError)>,
    /// Saves asked for through the palette: the number of commands
    /// produced before each.
    pub saves: Vec<usize>,
}

/// Replays `trace` through a fresh session onto an empty log.
pub fn replay(trace: &Trace) -> Result<Replay, TraceError> {
    let mut session = trace.header.session()?;
    let mut log = OpLog::new();
    let mut commands = Vec::new();
    let mut rejected = Vec::new();
    let mut saves = Vec::new();
    for frame in &trace.frames {
        if let Some(cmd) = session.step(frame, log.document()) {
            if let Err(e) = log.apply_command(&cmd) {
                rejected.push((commands.len(), e));
            }
            commands.push(cmd);
        }
        for _ in 0..session.take_save_requests() {
            saves.push(commands.len());
        }
    }
    Ok(Replay {
        commands,
        log,
        rejected,
        saves,
    })
}
