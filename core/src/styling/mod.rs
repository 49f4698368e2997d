//! Variational curve and surface styling with curve networks, after
//! Wesche & Droske (paper `variational-curve-surface-styling`, §2-6;
//! SPEC.md §3).
//!
//! - [`curve`]: cubic B-spline curves from tracked samples (§5.1).
//! - [`budget`]: limits on the memory and work an op may ask for.
//! - [`energy`]: bend, stretch, attractor and shape-preserving energies as
//!   sparse quadratic forms (§2.2).
//! - [`solver`]: the constrained minimization (eq. 6-7) with faer's sparse
//!   LDLᵀ, constraints by elimination, factorization reused across frames.
//! - [`tools`]: curve smoother, sharpener, puller (§3).
//! - [`attract`]: point, line, plane and curve attractors as a tool (§2.2).
//! - [`frame`]: the modeling frame held by the non-dominant hand (§5.4).
//! - [`surface`]: surface smoother, sharpener, puller on uniform bicubic
//!   B-splines with a fixed boundary (§4); [`surface_hold`]: those tools
//!   held along a pointer path on a patch (local, bounded per frame,
//!   stopping before an overhang).
//! - [`network`]: the curve network object (§5), split by idea into
//!   [`junction`] (weaving curves in, keeping them connected, §5.1),
//!   [`loops`] (pieces and loops, §5.2) and [`patch`] (patches, §5.3).
//! - [`ngon`]: n-sided patches (5..=16 sides), transfinite and smooth
//!   inside, over the polygon domain of [`polygon`] (derivatives by [`jet`]).
//! - [`select`]: tool selection from the pointer pose (§6, Table 1).
//! - [`edits`]: the `curve_*` / `surface_*` ops' payloads and how each
//!   changes a [`CurveNetwork`].
//!
//! Choices: B-spline basis, interpolation and approximation come from
//! `core::nurbs`; the sparse factorization is faer's (no own sparse code).
//! Everything runs sequentially, so results are bit-identical on any
//! number of threads.

// Negated comparisons reject NaN on purpose; index loops read best for
// the assembly code.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

pub mod attract;
pub mod budget;
pub mod curve;
pub mod edits;
pub mod energy;
mod error;
pub mod frame;
pub mod jet;
pub mod junction;
pub mod loops;
pub mod network;
pub mod ngon;
pub mod patch;
pub mod polygon;
pub mod select;
pub mod solver;
pub mod surface;
pub mod surface_hold;
pub mod tools;

pub use attract::{AttractParams, Attractor};
pub use budget::Budget;
pub use curve::{fit_curve, fit_curve_within, FitMode, SplineCurve};
pub use edits::{
    CurveAttract, CurveDelete, CurveDraw, CurveDrawInFrame, CurveFillAuto, CurveFillLoop, CurveId,
    CurveNetworkCreate, CurvePull, CurveSharpen, CurveSmooth, PatchId, SurfaceEquilibrium,
    SurfacePull, SurfaceSharpen, SurfaceSmooth,
};
pub use error::StylingError;
pub use frame::{stroke_in_held_frame, HeldStroke, ModelingFrame};
pub use network::{CurveNetwork, Node, Patch, Piece};

#[cfg(test)]
mod attract_tests;
#[cfg(test)]
mod budget_tests;
#[cfg(test)]
mod frame_tests;
#[cfg(test)]
pub(crate) mod hold_tests;
#[cfg(test)]
mod net_tests;
#[cfg(test)]
mod ngon_tests;
#[cfg(test)]
mod props_tests;
#[cfg(test)]
mod tests;
