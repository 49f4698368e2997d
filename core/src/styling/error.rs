//! Errors of the styling system.

use crate::nurbs::NurbsError;

/// Why a styling operation failed. Ops leave the document unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StylingError {
    /// A curve needs at least 4 tracked samples.
    #[error("a curve needs at least 4 samples, got {0}")]
    TooFewSamples(usize),
    /// Two consecutive samples coincide (closer than 1e-9).
    #[error("samples {0} and {1} coincide")]
    CoincidentSamples(usize, usize),
    /// A sample is NaN or infinite.
    #[error("sample {0} is not finite")]
    NonFiniteSample(usize),
    /// A value is NaN or infinite.
    #[error("{0} has non-finite values")]
    NonFinite(&'static str),
    /// A parameter is out of range.
    #[error("bad parameter: {0}")]
    BadParameter(&'static str),
    /// A curve's knots or control points are invalid.
    #[error("bad curve: {0}")]
    BadCurve(String),
    /// The curve index names no curve (deleted, or never drawn).
    #[error("curve {0} does not exist (deleted, or never drawn)")]
    NoCurve(usize),
    /// The patch index names no patch.
    #[error("patch {0} does not exist")]
    NoPatch(usize),
    /// The picked curve pieces do not form a closed loop.
    #[error("the picked pieces do not form a closed loop: {0}")]
    LoopNotClosed(String),
    /// Only loops of 3 to [`super::ngon::MAX_SIDES`] pieces can be filled.
    #[error("a loop of {0} pieces cannot be filled (3 to 16 supported)")]
    LoopSize(usize),
    /// n-sided patches (n > 4) need an even mesh resolution.
    #[error("loops of more than 4 pieces need an even network resolution (it is {0})")]
    OddResolution(u32),
    /// The loop is already filled.
    #[error("this loop is already filled by patch {0}")]
    AlreadyFilled(usize),
    /// Junction constraints on one curve are too close to each other to hold.
    #[error("junction constraints on curve {0} are degenerate")]
    DegenerateJunctions(usize),
    /// An input asks for more memory or work than the budget allows
    /// ([`super::budget::Budget`]): reduce the parameter named.
    #[error(transparent)]
    OverBudget(#[from] crate::budget::OverBudget),
    /// The sparse solver failed.
    #[error("solver: {0}")]
    Solver(String),
    /// An error from the NURBS code.
    #[error(transparent)]
    Nurbs(#[from] NurbsError),
}
