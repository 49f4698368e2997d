//! What counts as zero ([`LENGTH_EPS`]) and as a number ([`all_finite`]).

/// Lengths below this (in model units, metres) are treated as zero.
pub const LENGTH_EPS: f64 = 1e-12;

/// True when every component is finite.
pub fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}
