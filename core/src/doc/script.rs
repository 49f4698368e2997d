//! Op scripts: JSON lines (`.jsonl`), one op per line, run in order.
//!
//! Besides ops, a line may be `{"op":"undo"}` or `{"op":"redo"}`. Blank
//! lines and lines starting with `#` are skipped. A line may carry
//! `"op_version": N`, the op format version it was written for; versions
//! newer than [`OP_FORMAT_VERSION`] are refused. Errors name the 1-based
//! line.
//!
//! Files written before the key was renamed carry `"v": N`; it is still
//! read as the version on ops that have no field `v` (`gc_shift` and
//! `gc_insert_section` do, which is why the key moved: no op may have a
//! field named [`VERSION_KEY`], and a test checks the schema for it).

use serde_json::Value;

use super::{LogError, Op, OpLog, OP_NAMES};

/// The version of the op encoding this build writes and reads: new op
/// kinds and new optional fields keep the version; anything that changes
/// the meaning of an existing field bumps it.
pub const OP_FORMAT_VERSION: u32 = 1;

/// The key of a script line's format version.
pub const VERSION_KEY: &str = "op_version";

/// The key older files used for the format version.
const OLD_VERSION_KEY: &str = "v";

/// One command of a script.
#[derive(Clone, Debug, PartialEq)]
pub enum ScriptCommand {
    /// Apply an op.
    Op(Op),
    /// Undo the last op.
    Undo,
    /// Redo the next op.
    Redo,
}

impl ScriptCommand {
    /// The op's name (`gc_bend`, ...), or `undo` / `redo`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Op(op) => op.name(),
            Self::Undo => "undo",
            Self::Redo => "redo",
        }
    }
}

/// A command and the line it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct ScriptLine {
    /// 1-based line number.
    pub line: usize,
    /// The command.
    pub command: ScriptCommand,
}

/// A script line that could not be parsed or run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("script line {line}: {kind}")]
pub struct ScriptError {
    /// 1-based line number.
    pub line: usize,
    /// What went wrong.
    pub kind: ScriptErrorKind,
}

/// What went wrong on a script line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ScriptErrorKind {
    /// The line is not valid JSON, or a field is missing or mistyped.
    #[error("{0}")]
    Json(String),
    /// The line is JSON but not an object with a string `"op"` field.
    #[error("expected an object with a string \"op\" field, like {{\"op\":\"add_solid\",...}}")]
    NotAnOp,
    /// The `"op"` names no known op.
    #[error("unknown op `{name}`; known ops: undo, redo, {}", OP_NAMES.join(", "))]
    UnknownOp {
        /// The name given.
        name: String,
    },
    /// The line was written for a newer op format.
    #[error(
        "op format version {0} is newer than this build's {OP_FORMAT_VERSION}; update Shapewright"
    )]
    UnsupportedVersion(u64),
    /// The op was parsed but failed when run.
    #[error(transparent)]
    Log(#[from] LogError),
}

/// Parses a whole script. Stops at the first bad line.
pub fn parse_script(text: &str) -> Result<Vec<ScriptLine>, ScriptError> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let trimmed = raw.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let command = parse_line(trimmed).map_err(|kind| ScriptError { line, kind })?;
        out.push(ScriptLine { line, command });
    }
    Ok(out)
}

fn parse_line(text: &str) -> Result<ScriptCommand, ScriptErrorKind> {
    let mut value: Value =
        serde_json::from_str(text).map_err(|e| ScriptErrorKind::Json(e.to_string()))?;
    let obj = value.as_object_mut().ok_or(ScriptErrorKind::NotAnOp)?;
    let name = obj
        .get("op")
        .and_then(Value::as_str)
        .ok_or(ScriptErrorKind::NotAnOp)?
        .to_owned();
    let old_key = !super::schema::op_has_field(&name, OLD_VERSION_KEY);
    for key in [VERSION_KEY, OLD_VERSION_KEY] {
        if key == OLD_VERSION_KEY && !old_key {
            continue;
        }
        if let Some(v) = obj.shift_remove(key) {
            let v = v.as_u64().ok_or_else(|| {
                ScriptErrorKind::Json(format!("\"{key}\" must be a positive integer"))
            })?;
            if v > OP_FORMAT_VERSION as u64 {
                return Err(ScriptErrorKind::UnsupportedVersion(v));
            }
        }
    }
    match name.as_str() {
        "undo" | "redo" if obj.len() == 1 => Ok(if name == "undo" {
            ScriptCommand::Undo
        } else {
            ScriptCommand::Redo
        }),
        "undo" | "redo" => Err(ScriptErrorKind::Json(format!("`{name}` takes no fields"))),
        n if OP_NAMES.contains(&n) => serde_json::from_value(value)
            .map(ScriptCommand::Op)
            .map_err(|e| ScriptErrorKind::Json(e.to_string())),
        _ => Err(ScriptErrorKind::UnknownOp { name }),
    }
}

/// Runs parsed script lines on `log`, stopping at the first failure. The
/// failing line changes nothing; earlier lines stay applied.
pub fn run_script(log: &mut OpLog, lines: &[ScriptLine]) -> Result<(), ScriptError> {
    run_script_with(log, lines, |_, _| {})
}

/// [`run_script`], calling `progress(done, total)` after each line (hosts
/// show progress for long scripts with it).
pub fn run_script_with(
    log: &mut OpLog,
    lines: &[ScriptLine],
    mut progress: impl FnMut(usize, usize),
) -> Result<(), ScriptError> {
    for (k, l) in lines.iter().enumerate() {
        log.command(&l.command).map_err(|e| ScriptError {
            line: l.line,
            kind: e.into(),
        })?;
        progress(k + 1, lines.len());
    }
    Ok(())
}

impl OpLog {
    /// Applies one command: an op ([`OpLog::apply`]), an undo or a redo.
    /// Scripts, traces, the tools' sessions and both hosts apply commands
    /// through this one method.
    pub fn apply_command(&mut self, cmd: &ScriptCommand) -> Result<(), LogError> {
        self.command(cmd)?;
        #[cfg(test)]
        if let ScriptCommand::Op(op) = cmd {
            applied::record(op);
        }
        Ok(())
    }

    /// [`OpLog::apply_command`] unrecorded: a script's lines are applied
    /// by hand, not by a tool, so the reach table's test does not count
    /// them.
    fn command(&mut self, cmd: &ScriptCommand) -> Result<(), LogError> {
        match cmd {
            ScriptCommand::Op(op) => self.apply(op.clone()).map(|_| ()),
            ScriptCommand::Undo => self.undo(),
            ScriptCommand::Redo => self.redo(),
        }
    }
}

/// The ops a test got into a log through [`OpLog::apply_command`], per
/// test thread: the headset reach table's test runs the test each row
/// names and asks whether that row's op was among them.
#[cfg(test)]
pub(crate) mod applied {
    use std::cell::RefCell;

    thread_local! {
        static OPS: RefCell<Vec<&'static str>> = const { RefCell::new(Vec::new()) };
    }

    /// Records `op` by its name, and a part edit also by its kind
    /// (`gc_edit_part:bend`, ...): the reach table's rows for `gc_bend`
    /// and the like are reached through that kind.
    pub(crate) fn record(op: &crate::doc::Op) {
        use crate::assembly::PartEdit;
        let kind = match op {
            crate::doc::Op::GcEditPart(e) => Some(match e.edit.edit {
                PartEdit::Bend { .. } => "gc_edit_part:bend",
                PartEdit::Resize { .. } => "gc_edit_part:resize",
                PartEdit::Shift { .. } => "gc_edit_part:shift",
                PartEdit::Twist { .. } => "gc_edit_part:twist",
            }),
            _ => None,
        };
        OPS.with(|o| {
            o.borrow_mut()
                .extend(std::iter::once(op.name()).chain(kind))
        });
    }

    /// The ops applied on this thread since the last call.
    pub(crate) fn take() -> Vec<&'static str> {
        OPS.with(|o| std::mem::take(&mut *o.borrow_mut()))
    }
}
