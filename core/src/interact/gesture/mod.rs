//! The hand gesture classifier of paper 1 (gc-assembly, §4): OPEN, FIST,
//! POINT and PINCH (open or closed, with the finger gap as a value), plus
//! DOWN when the hand is below the centre of the body.
//!
//! Choices:
//! - **Features, not a learned model.** Each finger's curl is the sum of the
//!   bend angles at MCP, PIP and DIP (from joint positions, so it does not
//!   depend on the hand's orientation or on joint rotations, which runtimes
//!   estimate less well), normalized to `[0, 1]`; the pinch gap is the
//!   thumb-tip to index-tip distance, compared relative to the palm length
//!   so that small and large hands classify alike. Four rules on these
//!   features are transparent and need no training data.
//! - **Hysteresis:** every class has a strict region to enter it and a
//!   wider one to stay in it ([`GestureSettings::margin`]), and PINCH
//!   open/closed has two gap thresholds.
//! - **Debounce:** a new class is output only after it was seen for
//!   [`GestureSettings::debounce`] seconds in a row. Frames that fit no
//!   class keep the current output; after [`GestureSettings::ambiguous_timeout`]
//!   seconds of them the output becomes [`Gesture::None`].
//! - Features are smoothed with an exponential filter (time constant
//!   [`GestureSettings::smoothing`]) to take out tracking jitter.
//! - A lost hand outputs [`Gesture::None`] at once (no debounce: tools must
//!   stop acting on a hand they cannot see).

pub(crate) mod bimanual;
pub(crate) mod controller_hand;
pub(crate) mod handmodel;
pub(crate) mod similarity;

mod classifier;
mod features;
mod label;

pub use classifier::{GestureClassifier, GestureSettings, GestureState};
pub use features::HandFeatures;
pub use label::{Gesture, GestureLabel};
