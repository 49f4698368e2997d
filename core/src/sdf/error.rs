//! [`SdfError`]: what can go wrong in the SDF system.

use crate::math::TransformError;
use crate::solid::SolidError;

/// Why an SDF op or library call failed. Nothing was changed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SdfError {
    /// The grid step is outside the supported range.
    #[error("grid step {0} is outside 0.004..=0.012 (the default is 0.01)")]
    BadStep(f64),
    /// The operand index names no pending operand.
    #[error("volume has {len} pending operands; operand {index} does not exist")]
    BadOperand {
        /// The index given.
        index: usize,
        /// Number of pending operands.
        len: usize,
    },
    /// No library or imported component has this name.
    #[error("no component named `{0}` (see sdf::library::STARTER_NAMES, or import one first)")]
    UnknownComponent(String),
    /// A user component with this name exists already.
    #[error("a component named `{0}` exists already; pick another name")]
    DuplicateComponent(String),
    /// The transform is NaN, infinite, has a zero rotation or a zero scale.
    #[error(transparent)]
    Transform(#[from] TransformError),
    /// The transform's matrix cannot be inverted.
    #[error("the placement's matrix is singular; every scale must be well away from zero")]
    SingularTransform,
    /// An analytic component's sizes are invalid.
    #[error(transparent)]
    Solid(#[from] SolidError),
    /// A hand position is NaN or infinite (tracking lost).
    #[error("a hand position is not finite (tracking lost?)")]
    NonFiniteHands,
    /// The two hands started too close together to define a ratio.
    #[error("the hands were {distance} apart when the two-hand scale began; they must be at least 1e-6 apart")]
    HandsTooClose {
        /// Their distance.
        distance: f64,
    },
    /// The mesh given to the library is not a closed, oriented 2-manifold.
    #[error("component mesh is not a closed oriented 2-manifold: {0}")]
    BadMesh(String),
    /// The grid would exceed the memory budget ([`super::budget`]).
    /// Its parameter is `step` (a larger step, or the operand scaled
    /// down, needs less).
    #[error(transparent)]
    OverBudget(#[from] crate::budget::OverBudget),
    /// The op would take longer than the time limit ([`super::budget`]).
    #[error("{what} would take about {seconds:.1} s on this machine, over the {limit} s limit; use a larger step, or fewer or smaller operands")]
    TooSlow {
        /// What would take so long.
        what: String,
        /// The estimate, in seconds.
        seconds: f64,
        /// The limit, in seconds.
        limit: f64,
    },
    /// Moving the fused result by a transform that is not a similarity
    /// (its scale differs per axis) cannot be done exactly by moving the
    /// operands: make the result a component first and scale that.
    #[error("the fused result can only be moved by a uniform scale, got {0:?}; make it a component (sdf_copy_fused) and scale the copy")]
    NotSimilarity([f64; 3]),
    /// The fused result is empty: there is nothing to move or copy.
    #[error("the volume's fused result is empty; update some operands first")]
    EmptyResult,
    /// A user component needs a name to be picked by.
    #[error("the component name is empty; give the imported component a name")]
    EmptyComponentName,
    /// A reused object, a copy or a moved result would not keep its shape
    /// at the volume's grid step: resampled there it loses pieces or
    /// tunnels, or (a moved result, a shrunk copy) more than 1% of its
    /// volume (its thinnest parts are below about two grid cells).
    #[error("{what} would come out as {got} instead of {want_pieces} piece(s) of genus {want_genus} (a moved result or a shrunk copy also within 1% of its volume) at the grid step {step} m: its thinnest parts are below about two grid cells there; use a finer step (sdf_set_step, down to 0.004) or make it larger")]
    TooThin {
        /// What was reused (`object #3`, `the copy of the result`, ...).
        what: String,
        /// The grid step it was checked at.
        step: f64,
        /// The source's genus.
        want_genus: i64,
        /// The source's number of pieces.
        want_pieces: usize,
        /// What the grid gave.
        got: String,
    },
    /// A reused object's walls are thinner than two grid cells over more
    /// than [`super::reuse::THIN_AREA_TOL`] of its surface: sampled at
    /// this step it would lose them, or much of its volume.
    #[error("{what} has walls thinner than {wall} m (two grid cells) over {percent:.1}% of its surface at the grid step {step} m, which the grid would thin or lose; use a finer step (sdf_set_step, down to 0.004) or make it larger")]
    ThinWalls {
        /// What was reused (`object #3`).
        what: String,
        /// The volume's grid step.
        step: f64,
        /// The thinnest wall the step keeps (two cells).
        wall: f64,
        /// How much of the surface lies on thinner walls, in percent.
        percent: f64,
    },
    /// `sdf_update` with no pending operand.
    #[error("nothing to update: the volume has no pending operands")]
    NothingPending,
}
