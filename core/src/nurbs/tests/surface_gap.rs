//! The largest distance between two surfaces on a grid of parameters.
//!
//! A module of `nurbs::tests`, and included by path in `gc::tests` too:
//! both test modules are private to their parents, so neither can name
//! the other's items.

use crate::nurbs::NurbsSurface;

/// The largest distance between `a` and `b` at the `(n + 1)²` parameters
/// `(i / n, j / n)`, `0 <= i, j <= n`.
pub(crate) fn max_gap(a: &NurbsSurface, b: &NurbsSurface, n: usize) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..=n {
        for j in 0..=n {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            worst = worst.max((a.point(u, v) - b.point(u, v)).length());
        }
    }
    worst
}
