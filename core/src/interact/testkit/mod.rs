//! Test generators (behind the `testkit` feature; always on in the core's
//! own tests): the scripted puppet that records traces, the labelled hand
//! sequences the gesture classifier is scored on, and the puppet scripts of
//! the checked-in traces (`tests/data/{mug,teapot}*.trace.jsonl`, the CSG
//! cup and the bust), and the [`Driver`] that runs a puppet against a
//! modeler session in lockstep so a script can pick palette items where
//! the session shows them. Hosts never need them; the benches, `make_traces` and
//! the hosts' integration tests do.

pub(crate) mod gc_traces;
mod hand_sequences;
mod modeler;
mod puppet;

#[cfg(test)]
pub(crate) mod ctl_traces;
#[cfg(test)]
mod gesture_accuracy;
#[cfg(test)]
mod lamp_trace;

pub use gc_traces::{mug_controller_trace, mug_trace, teapot_controller_trace, teapot_trace};
pub use hand_sequences::{
    hand_sample, labelled_sequence, score_sequence, GestureScore, LabelledFrame, SequenceSettings,
};
pub use modeler::Driver;
pub use puppet::{feed_quietly, hand_params, Button, Puppet};
