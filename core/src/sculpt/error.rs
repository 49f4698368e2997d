//! [`SculptError`]: everything a sculpt op can refuse, with what was wrong.

/// Why a sculpt op (or a half-edge conversion) was refused. The document is
/// unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SculptError {
    /// The input mesh is not a closed oriented 2-manifold.
    #[error("the {what} mesh is not a closed oriented 2-manifold: {problems}")]
    NotClosedManifold {
        /// Which mesh (`base`, `brush`, ...).
        what: &'static str,
        /// What the validator found.
        problems: String,
    },
    /// The input mesh has a triangle index past its positions or a
    /// repeated index in a triangle.
    #[error("the {what} mesh has a bad triangle {triangle}: {reason}")]
    BadTriangle {
        /// Which mesh.
        what: &'static str,
        /// Index of the triangle.
        triangle: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A number is NaN or infinite (lost tracking, corrupted script).
    #[error("{field} is not finite: {value:?}")]
    NonFinite {
        /// Which parameter.
        field: String,
        /// The values given.
        value: Vec<f64>,
    },
    /// A size that must be positive is zero or negative.
    #[error("{field} must be positive, got {value}")]
    NonPositive {
        /// Which parameter.
        field: String,
        /// The value given.
        value: f64,
    },
    /// A parameter is outside its allowed range.
    #[error("{field} = {value} is out of range: {range}")]
    OutOfRange {
        /// Which parameter.
        field: String,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        range: &'static str,
    },
    /// A rotation quaternion has (near) zero length.
    #[error("{field} is a zero quaternion; give [x, y, z, w] with w = 1 for no rotation")]
    ZeroRotation {
        /// Which parameter.
        field: String,
    },
    /// A stroke has no samples.
    #[error("a stroke needs at least one sample")]
    EmptyStroke,
    /// A distance grid's value count does not match its dimensions, or a
    /// dimension is below 2.
    #[error("distance grid has dims {dims:?} ({expected} values expected) but {found} values")]
    BadGrid {
        /// The grid dimensions.
        dims: [u32; 3],
        /// Values the dimensions call for.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// The sculpt model placement scales non-uniformly (brush distances
    /// would not be distances in model space).
    #[error("a sculpt mesh's transform must scale uniformly, got {0:?}")]
    NonUniformScale([f64; 3]),
    /// Building the base mesh would exceed the vertex budget.
    #[error("the base mesh would have {vertices} vertices, above the limit of {limit}")]
    TooLarge {
        /// Vertices the parameters ask for.
        vertices: u64,
        /// The limit.
        limit: u64,
    },
    /// A mesh brush's grid would have too many samples.
    #[error("the brush grid would have {samples} samples, above the limit of {limit}; use a larger step")]
    BrushTooLarge {
        /// Samples the step, padding and mesh size ask for.
        samples: u64,
        /// The limit.
        limit: u64,
    },
    /// A stroke would take more memory or work than the budget allows
    /// ([`super::budget`]): reduce or fix the parameter named.
    #[error(transparent)]
    OverBudget(#[from] crate::budget::OverBudget),
    /// A sculpt op would take longer than one may on this machine
    /// ([`super::budget::MAX_SECONDS`]): estimated before it runs, or (for
    /// a stroke whose surface made it do more than estimated) measured by
    /// the work it did before it stopped. Reduce or fix the parameter
    /// named: fewer or closer samples, a larger `max_edge_rel`, a coarser
    /// brush grid or base mesh.
    #[error("{field}: {what} would take about {seconds:.1} s on this machine, over the limit of {limit} s ({detail})")]
    TooSlow {
        /// The parameter that sized the request.
        field: String,
        /// What was estimated.
        what: &'static str,
        /// The estimate, in seconds (may be infinite).
        seconds: f64,
        /// The limit, in seconds.
        limit: f64,
        /// What the estimate counted.
        detail: String,
    },
    /// The half-edge structure failed its validity check (an internal
    /// invariant; reported rather than panicking).
    #[error("half-edge mesh invalid: {0}")]
    Invalid(String),
    /// The stroke's mirror plane is not a plane.
    #[error(transparent)]
    Mirror(#[from] crate::math::MirrorError),
}
