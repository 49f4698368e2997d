//! Errors of the sketch pipeline.

use crate::nurbs::NurbsError;

/// Why a stroke could not be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SketchError {
    /// Too few points for the operation.
    #[error("the stroke has {got} points, at least {need} are needed")]
    TooFewPoints {
        /// Points given (after removing repeats).
        got: usize,
        /// Points needed.
        need: usize,
    },
    /// The stroke has (nearly) zero length or encloses no area.
    #[error("the stroke has zero length or encloses no area")]
    ZeroLength,
    /// A NaN or infinite coordinate.
    #[error("the stroke has a non-finite coordinate at point {0}")]
    NonFinite(usize),
    /// A closed section sketch crosses itself.
    #[error("the section sketch intersects itself")]
    SelfIntersecting,
    /// The sketch plane normal is zero or non-finite.
    #[error("the sketch plane normal is zero or non-finite")]
    BadPlane,
    /// A parameter (tolerance, sample count) is out of range.
    #[error("{what} is out of range: {value}")]
    BadParameter {
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// Curve fitting failed.
    #[error(transparent)]
    Nurbs(#[from] NurbsError),
}
