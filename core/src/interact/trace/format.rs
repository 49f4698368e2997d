//! The trace file: its header ([`TraceHeader`], [`ModelPlacement`]), the
//! [`Trace`] of raw frames read from and written to JSON lines, and
//! [`TraceError`].

use serde::{Deserialize, Serialize};

use crate::math::{DQuat, DVec3};

use crate::interact::gesture::similarity::Similarity;
use crate::interact::input::{InputFrame, STAGE_FROM_Z_UP};
use crate::interact::session::Session;
use crate::interact::tools::{tool_named, UnknownTool};

/// The `format` field of every trace header.
pub const TRACE_FORMAT: &str = "shapewright-trace";
/// The trace version this build writes and reads.
pub const TRACE_VERSION: u32 = 1;

/// Where the model sits in the stage: `p -> translate + rotate * (scale * p)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelPlacement {
    /// Translation, metres.
    pub translate: [f64; 3],
    /// Rotation `[x, y, z, w]`.
    pub rotate: [f64; 4],
    /// Uniform scale.
    pub scale: f64,
}

impl ModelPlacement {
    /// The placement as a similarity, if finite with a positive scale.
    pub fn similarity(&self) -> Option<Similarity> {
        let q = DQuat::from_array(self.rotate);
        if !q.is_finite() || q.length_squared() < 1e-12 {
            return None;
        }
        let s = Similarity {
            translate: DVec3::from_array(self.translate),
            rotate: q.normalize(),
            scale: self.scale,
        };
        s.is_valid().then_some(s)
    }

    /// The default: the model's +Z up (stage +Y), its +Y away from the
    /// user (stage -Z), its origin 0.8 m high and 0.5 m ahead (a desk).
    pub fn desk() -> ModelPlacement {
        ModelPlacement {
            translate: [0.0, 0.8, -0.5],
            // The exact quarter turn, not `from_rotation_x(-π/2)`: its
            // sine and cosine come from the platform's libm (glam), one
            // ulp off here, so a session's ops could differ by platform.
            rotate: STAGE_FROM_Z_UP.to_array(),
            scale: 1.0,
        }
    }
}

/// The first line of a trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TraceHeader {
    /// Always [`TRACE_FORMAT`].
    pub format: String,
    /// The version written ([`TRACE_VERSION`]).
    pub version: u32,
    /// Nominal frames per second.
    pub fps: f64,
    /// Where the model sits in the stage.
    pub model: ModelPlacement,
    /// The tool the session runs (`"object"`).
    pub tool: String,
    /// What the trace shows.
    #[serde(default)]
    pub note: String,
    /// A modeler session: every tool, switched through the palette, with
    /// [`TraceHeader::tool`] active first ([`Session::modeler`]); `false`
    /// (and absent, in traces written before it): that tool alone.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub modeler: bool,
}

impl TraceHeader {
    /// A fresh session as this header describes it.
    pub fn session(&self) -> Result<Session, TraceError> {
        let model = self.model.similarity().ok_or(TraceError::Model)?;
        Ok(if self.modeler {
            Session::modeler(&self.tool, crate::interact::input::Hand::Right, model)?
        } else {
            Session::new(tool_named(&self.tool)?, model)
        })
    }
}

/// A recorded session.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    /// The header.
    pub header: TraceHeader,
    /// The raw frames, in order.
    pub frames: Vec<InputFrame>,
}

/// Why a trace could not be read or replayed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TraceError {
    /// The text has no header line.
    #[error("empty trace: the first line must be a header like {{\"format\":\"{TRACE_FORMAT}\",\"version\":{TRACE_VERSION},...}}")]
    Empty,
    /// The first line is not a valid header.
    #[error("trace header (line 1): {0}")]
    Header(String),
    /// The header names another format.
    #[error("not a Shapewright trace: format is `{0}`, expected `{TRACE_FORMAT}`")]
    Format(String),
    /// The trace was written by a newer version.
    #[error("trace version {0} is newer than this build's {TRACE_VERSION}; update Shapewright")]
    Version(u32),
    /// A frame line is not a valid frame.
    #[error("trace line {line}: {message}")]
    Frame {
        /// 1-based line number.
        line: usize,
        /// What was wrong.
        message: String,
    },
    /// The header's model placement is not finite or has a non-positive scale.
    #[error("trace header: model placement must be finite with a positive scale")]
    Model,
    /// The header names a tool this build does not have.
    #[error("trace header: {0}")]
    UnknownTool(#[from] UnknownTool),
}

impl Trace {
    /// A trace with `header` and no frames.
    pub fn new(header: TraceHeader) -> Trace {
        Trace {
            header,
            frames: Vec::new(),
        }
    }

    /// The trace as JSON lines.
    pub fn to_jsonl(&self) -> String {
        let mut out = serde_json::to_string(&self.header).unwrap_or_default();
        out.push('\n');
        for f in &self.frames {
            out.push_str(&serde_json::to_string(f).unwrap_or_default());
            out.push('\n');
        }
        out
    }

    /// Parses JSON lines. Blank lines are skipped.
    pub fn from_jsonl(text: &str) -> Result<Trace, TraceError> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let (_, first) = lines.next().ok_or(TraceError::Empty)?;
        let header: TraceHeader =
            serde_json::from_str(first).map_err(|e| TraceError::Header(e.to_string()))?;
        if header.format != TRACE_FORMAT {
            return Err(TraceError::Format(header.format));
        }
        if header.version > TRACE_VERSION {
            return Err(TraceError::Version(header.version));
        }
        let frames = lines
            .map(|(i, l)| {
                serde_json::from_str(l).map_err(|e| TraceError::Frame {
                    line: i + 1,
                    message: e.to_string(),
                })
            })
            .collect::<Result<_, _>>()?;
        Ok(Trace { header, frames })
    }
}
