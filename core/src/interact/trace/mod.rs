//! Recorded input traces and their replay.
//!
//! A trace is JSON lines (`NAME.trace.jsonl`): the first line is a
//! [`TraceHeader`] (format name, version, frame rate, where the model sits
//! in the world, the tool), every further line one raw [`InputFrame`](crate::interact::InputFrame),
//! exactly as a host delivered it (NaNs and invalid samples included, so a
//! replay exercises the sanitizer too). JSON lines rather than a binary
//! format: traces are small (controller frames are ~400 bytes), diff well
//! and open in any editor; serde_json prints floats in shortest round-trip
//! form, so replays are bit-exact.
//!
//! [`replay`] runs a fresh [`Session`](crate::interact::Session) over the frames against an
//! [`OpLog`](crate::doc::OpLog), applying each command as it is produced (tools read the
//! document, e.g. to pick), and returns the commands and the log.

#[cfg(test)]
mod fixture_tests;

mod format;
mod replay;

pub use format::{ModelPlacement, Trace, TraceError, TraceHeader, TRACE_FORMAT, TRACE_VERSION};
pub use replay::{replay, Replay};
