//! The host's `--record` file (one JSON object a line: an input frame or
//! a lifecycle event), shared by `tests/testrt.rs` and `tests/monado.rs`.

use shapewright::interact::InputFrame;
use shapewright_xr::xr::LifecycleEvent;

#[derive(serde::Deserialize)]
#[serde(rename_all = "snake_case")]
enum Line {
    Frame(Box<InputFrame>),
    Lifecycle(LifecycleEvent),
}

/// The session states, in order, of a run that reaches FOCUSED and that
/// the host ends itself (a frame limit or a quit): OpenXR's whole
/// lifecycle, each state once on the way in and out.
pub const HOST_ENDED_RUN: [&str; 10] = [
    "IDLE",
    "READY",
    "SYNCHRONIZED",
    "VISIBLE",
    "FOCUSED",
    "VISIBLE",
    "SYNCHRONIZED",
    "STOPPING",
    "IDLE",
    "EXITING",
];

/// The record's frames and events, in file order; panics on a line that
/// is not a frame or an event.
pub fn parse(text: &str) -> (Vec<InputFrame>, Vec<LifecycleEvent>) {
    let mut frames = Vec::new();
    let mut events = Vec::new();
    for l in text.lines() {
        match serde_json::from_str::<Line>(l).unwrap_or_else(|e| panic!("bad record line {l}: {e}"))
        {
            Line::Frame(f) => frames.push(*f),
            Line::Lifecycle(e) => events.push(e),
        }
    }
    (frames, events)
}
