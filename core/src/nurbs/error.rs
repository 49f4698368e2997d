//! Errors of NURBS construction and fitting.

/// Why a NURBS curve or surface could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NurbsError {
    /// The degree is zero or too high for the number of control points.
    #[error("degree {degree} is not possible with {n_ctrl} control points")]
    BadDegree {
        /// The degree asked for.
        degree: usize,
        /// The number of control points.
        n_ctrl: usize,
    },
    /// The knot vector has the wrong length, decreases, or has an empty domain.
    #[error("invalid knot vector: {0}")]
    BadKnots(&'static str),
    /// A weight is zero, negative or non-finite.
    #[error("weight {index} is {weight}; weights must be positive and finite")]
    BadWeight {
        /// Control point index.
        index: usize,
        /// The weight.
        weight: f64,
    },
    /// A coordinate or parameter is NaN or infinite.
    #[error("non-finite input ({0})")]
    NonFinite(&'static str),
    /// Fewer points than the construction needs.
    #[error("{got} points given, at least {need} needed")]
    TooFewPoints {
        /// Points given.
        got: usize,
        /// Points needed.
        need: usize,
    },
    /// Consecutive data points coincide, so chord-length parameters are
    /// undefined.
    #[error("data points {0} and {1} coincide")]
    CoincidentPoints(usize, usize),
    /// Parameters are not strictly increasing.
    #[error("parameters must be strictly increasing (at index {0})")]
    BadParameters(usize),
    /// The linear system of an interpolation is singular.
    #[error("singular interpolation system")]
    Singular,
    /// Curves to be made compatible have different parameter domains.
    #[error("curves have different parameter domains")]
    DomainMismatch,
    /// Curves to be lofted must be given with one parameter per curve.
    #[error("{curves} curves but {params} parameters")]
    ParamCount {
        /// Number of curves.
        curves: usize,
        /// Number of parameters.
        params: usize,
    },
    /// A segment `[lo, hi]` was asked for outside the curve's domain
    /// `[a, b]`, or with `lo >= hi`.
    #[error("segment [{lo}, {hi}] is not inside the domain [{a}, {b}] (or is empty)")]
    SegmentOutside {
        /// Start asked for.
        lo: f64,
        /// End asked for.
        hi: f64,
        /// Domain start.
        a: f64,
        /// Domain end.
        b: f64,
    },
    /// A Coons patch cannot be written as one polynomial bicubic surface
    /// (a rational side, a side above cubic, a side not on `[0, 1]`).
    #[error("not a polynomial bicubic patch: {0}")]
    NotBicubic(&'static str),
    /// A displacement grid is not `n × n` with `n >= 4`.
    #[error("a displacement grid of {points} points is not {n}×{n} (n >= 4)")]
    DisplacementGrid {
        /// Points per side expected.
        n: usize,
        /// Points given.
        points: usize,
    },
}
