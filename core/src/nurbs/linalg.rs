//! A small dense solver (Gaussian elimination with partial pivoting) for
//! the interpolation and fitting systems, which are small (tens to a few
//! hundred unknowns) and solved once per edit. Deterministic: a fixed
//! elimination order, no threads.

use std::ops::{Mul, Sub};

use super::NurbsError;

/// Solves `a x = b` for a square row-major `n x n` matrix `a` and one
/// right-hand side per row (`b[i]` may be a point or a homogeneous point).
pub fn solve<T>(mut a: Vec<f64>, mut b: Vec<T>) -> Result<Vec<T>, NurbsError>
where
    T: Copy + Sub<Output = T> + Mul<f64, Output = T>,
{
    let n = b.len();
    debug_assert_eq!(a.len(), n * n);
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if !(scale > 0.0) || !scale.is_finite() {
        return Err(NurbsError::Singular);
    }
    for col in 0..n {
        let mut piv = col;
        let mut best = a[col * n + col].abs();
        for r in col + 1..n {
            let v = a[r * n + col].abs();
            if v > best {
                best = v;
                piv = r;
            }
        }
        if best <= scale * 1e-14 {
            return Err(NurbsError::Singular);
        }
        if piv != col {
            for c in 0..n {
                a.swap(col * n + c, piv * n + c);
            }
            b.swap(col, piv);
        }
        let d = a[col * n + col];
        for r in col + 1..n {
            let f = a[r * n + col] / d;
            if f == 0.0 {
                continue;
            }
            for c in col..n {
                a[r * n + c] -= f * a[col * n + c];
            }
            b[r] = b[r] - b[col] * f;
        }
    }
    let mut x = b.clone();
    for r in (0..n).rev() {
        let mut acc = b[r];
        for c in r + 1..n {
            acc = acc - x[c] * a[r * n + c];
        }
        x[r] = acc * (1.0 / a[r * n + r]);
    }
    Ok(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_small_system() {
        let a = vec![2.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 4.0];
        let x = solve(a.clone(), vec![3.0f64, 5.0, 5.0]).unwrap();
        for r in 0..3 {
            let s: f64 = (0..3).map(|c| a[r * 3 + c] * x[c]).sum();
            assert!((s - [3.0, 5.0, 5.0][r]).abs() < 1e-12);
        }
        assert_eq!(
            solve(vec![1.0, 2.0, 2.0, 4.0], vec![1.0f64, 2.0]),
            Err(NurbsError::Singular)
        );
    }
}
