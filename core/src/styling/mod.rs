//! Variational curve and surface styling with curve networks, after
//! Wesche & Droske (paper `variational-curve-surface-styling`, §2-6;
//! SPEC.md §3).
//!
//! - [`curve`]: cubic B-spline curves from tracked samples (§5.1).
//! - [`energy`]: bend, stretch, attractor and shape-preserving energies as
//!   sparse quadratic forms (§2.2).
//! - [`solver`]: the constrained minimization (eq. 6-7) with faer's sparse
//!   LDLᵀ, constraints by elimination, factorization reused across frames.
//! - [`tools`]: curve smoother, sharpener, puller (§3).
//! - [`surface`]: surface smoother, sharpener, puller on uniform bicubic
//!   B-splines with a fixed boundary (§4).
//! - [`network`]: curve networks, junctions, loops and patches (§5).
//! - [`ngon`]: n-sided patches (5..=8 sides) split into quads around a centre.
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

pub mod curve;
pub mod edits;
pub mod energy;
mod error;
pub mod network;
pub mod ngon;
pub mod select;
pub mod solver;
pub mod surface;
pub mod tools;

pub use curve::{fit_curve, FitMode, SplineCurve};
pub use edits::{
    CurveDelete, CurveDraw, CurveFillAuto, CurveFillLoop, CurveId, CurveNetworkCreate, CurvePull,
    CurveSharpen, CurveSmooth, PatchId, SurfaceEquilibrium, SurfacePull, SurfaceSharpen,
    SurfaceSmooth,
};
pub use error::StylingError;
pub use network::{CurveNetwork, Node, Patch, Piece};

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_net;
#[cfg(test)]
mod tests_props;
