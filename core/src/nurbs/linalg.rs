//! A dense solver (Gaussian elimination with partial pivoting) for the
//! interpolation and fitting systems, solved once per edit. Deterministic:
//! a fixed elimination order, no threads.
//!
//! The matrices are stored dense but are mostly zeros: a closed profile
//! through `n` points is a cyclic band (three or four entries a row), and
//! its elimination touches a handful of rows per column. Read column-wise
//! through a dense `n × n` array, a 4,096-point profile took 0.26 s and
//! 64 of them 17 s before the skin's budget could refuse them (issue 37).
//! So the elimination keeps, per row, the first column where it may be
//! nonzero, looks for the pivot only among the rows that reach the column,
//! and updates a row only at the pivot row's nonzero columns. Those are
//! exactly the operations of the textbook loop whose result is not `x -
//! f·0`: skipping them leaves every entry with the same bits (every zero
//! of the matrix is `+0.0`, and `x - f·(+0.0)` is `x`), so every solution
//! is bit-identical to the dense loop's (a test compares them).

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
    if !(scale > 0.0) || !scale.is_finite() || a.iter().any(|x| x.is_nan()) {
        return Err(NurbsError::Singular);
    }
    // `first[r]`: no column of row `r` before it is nonzero (among the
    // columns not yet eliminated). Rows are listed in `starts` by it.
    let mut first: Vec<usize> = (0..n)
        .map(|r| {
            a[r * n..(r + 1) * n]
                .iter()
                .position(|&x| x != 0.0)
                .unwrap_or(n)
        })
        .collect();
    let mut starts: Vec<Vec<usize>> = vec![Vec::new(); n + 1];
    for (r, &f) in first.iter().enumerate() {
        starts[f].push(r);
    }
    // Rows at or below the diagonal whose first possible nonzero is at or
    // before the current column, in row order.
    let mut reach: Vec<usize> = Vec::new();
    let mut nz: Vec<usize> = Vec::with_capacity(n);
    for col in 0..n {
        // Rows whose first nonzero is this column join; rows above it
        // have been pivots already.
        for &r in &starts[col] {
            if first[r] == col && r >= col {
                reach.push(r);
            }
        }
        reach.retain(|&r| r >= col);
        reach.sort_unstable();
        reach.dedup();
        let mut piv = col;
        let mut best = a[col * n + col].abs();
        for &r in reach.iter().filter(|&&r| r > col) {
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
            first.swap(col, piv);
            // `piv` was listed, and stays listed for the row moved there.
        }
        let d = a[col * n + col];
        nz.clear();
        nz.extend((col..n).filter(|&c| a[col * n + c] != 0.0));
        for &r in reach.iter().filter(|&&r| r > col) {
            let f = a[r * n + col] / d;
            if f == 0.0 {
                continue;
            }
            for &c in &nz {
                a[r * n + c] -= f * a[col * n + c];
            }
            b[r] = b[r] - b[col] * f;
        }
        // A listed row stays listed until it is the pivot (`first` is
        // read only for rows not listed yet, which no update touches).
        reach.retain(|&r| r > col);
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

    /// The textbook loop [`solve`] skips the zero updates of.
    fn solve_dense(mut a: Vec<f64>, mut b: Vec<f64>) -> Result<Vec<f64>, NurbsError> {
        let n = b.len();
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
                b[r] -= b[col] * f;
            }
        }
        let mut x = b.clone();
        for r in (0..n).rev() {
            let mut acc = b[r];
            for c in r + 1..n {
                acc -= x[c] * a[r * n + c];
            }
            x[r] = acc * (1.0 / a[r * n + r]);
        }
        Ok(x)
    }

    proptest::proptest! {
        /// Same bits as the dense loop on sparse and dense systems alike:
        /// random cyclic bands (the closed interpolation's shape, with
        /// rows shuffled so pivots move rows around), random sparse and
        /// full matrices, and singular ones.
        #[test]
        fn same_bits_as_the_dense_loop(
            n in 1usize..40,
            density in 0.0f64..1.0,
            band in proptest::bool::ANY,
            seed in proptest::num::u64::ANY,
        ) {
            let mut s = seed | 1;
            let mut next = || {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                (s >> 11) as f64 / (1u64 << 53) as f64
            };
            let mut a = vec![0.0; n * n];
            let mut rows: Vec<usize> = (0..n).collect();
            for i in (1..n).rev() {
                rows.swap(i, (next() * (i + 1) as f64) as usize % (i + 1));
            }
            for (r, &row) in rows.iter().enumerate() {
                for c in 0..n {
                    let near = (c + n - r % n) % n <= 3;
                    if (band && near) || (!band && next() < density) {
                        a[row * n + c] = next() - 0.3;
                    }
                }
            }
            let b: Vec<f64> = (0..n).map(|_| next() * 2.0 - 1.0).collect();
            let dense = solve_dense(a.clone(), b.clone());
            let ours = solve(a, b);
            match (dense, ours) {
                (Ok(x), Ok(y)) => {
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    proptest::prop_assert_eq!(bits(&x), bits(&y));
                }
                (x, y) => proptest::prop_assert_eq!(x.is_err(), y.is_err()),
            }
        }
    }
}
