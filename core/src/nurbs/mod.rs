//! NURBS curves and surfaces, our own implementation of Piegl & Tiller,
//! *The NURBS Book* (2nd ed.): basis functions (ch. 2), rational curves and
//! surfaces with homogeneous control points and their derivatives (ch. 3-4),
//! knot insertion and degree elevation (ch. 5), global and closed
//! interpolation and least-squares approximation (ch. 9), and skinning
//! (§10.3), plus tessellation helpers.
//!
//! Why our own code: the crate `curvo` (checked in FIELD-NOTES) lofts
//! without exact skinning (sections missed by ~1e-2) and its degree
//! elevation leaves zero weights or panics; the GC edits need sections
//! interpolated exactly and an insert that leaves the surface unchanged.
//!
//! Choices: control points are `DVec4` homogeneous `(w x, w y, w z, w)`;
//! closed curves are stored in clamped form (a periodic interpolant is
//! converted by knot insertion), so every curve has one code path; degree
//! elevation goes through Bézier decomposition (exact, C0 knot vector);
//! small dense linear systems are solved by pivoted Gaussian elimination
//! (deterministic). Uniform cubic B-splines and bicubic surfaces are the
//! special case `clamped_uniform_knots(n, 3)` / `periodic_uniform_knots`.

// Negated comparisons reject NaN on purpose (`!(x > 0.0)`), and the
// P&T algorithms read best with index loops.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

pub mod basis;
mod coons;
mod curve;
mod error;
mod interp;
mod linalg;
pub mod shapes;
mod skin;
mod surface;
mod tessellate;

pub use basis::{
    averaged_knots, basis_funs, clamped_uniform_knots, ders_basis_funs, find_span,
    knot_multiplicities, periodic_uniform_knots,
};
pub use coons::{coons_bicubic, knot_union, segment, CoonsSides};
pub use curve::{euclidean, homogeneous, NurbsCurve};
pub use error::NurbsError;
pub use interp::{
    approximate, approximate_to_tolerance, interpolate, interpolate_at, interpolate_closed,
    interpolate_natural_cubic, interpolate_natural_cubic_h, parameters, ParamMethod,
};
pub use linalg::solve;
pub use skin::{make_compatible, skin, skin_params, SkinV, KNOT_SNAP};
pub use surface::NurbsSurface;
pub use tessellate::{curve_polyline, knot_aligned_samples, uniform_samples};

#[cfg(test)]
mod tests;
