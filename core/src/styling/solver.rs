//! Sparse symmetric solves with fixed unknowns and a reused factorization.
//!
//! The constraint `D c = e` of the paper (eq. 7) fixes control points, so
//! it is applied by elimination, which makes it hold exactly: a fixed
//! unknown's row and column are zeroed and its diagonal set to 1, its value
//! moved to the right-hand side. The matrix keeps the full sparsity pattern
//! whatever is fixed, so the symbolic factorization (ordering, elimination
//! tree) is computed once per pattern and only the numeric LDLᵀ is redone
//! when weights change; when only the right-hand side changes (puller
//! targets, equilibrium terms, refreshed references) the factors are reused
//! as they are. faer's sparse LDLᵀ runs sequentially (`Par::Seq`), so the
//! result does not depend on the thread count. One step of iterative
//! refinement follows a solve whose residual is not already at rounding
//! level (FIELD-NOTES: LDLᵀ plus refinement): `‖b − A x‖∞ ≤ 16 ε (‖A‖∞
//! ‖x‖∞ + ‖b‖∞)` for every right-hand side, the normwise backward error a
//! stable solve reaches, skips it. The residual is computed either way;
//! the second triangular solve it saves was a quarter to 40% of a surface
//! frame's solve (0.46 → 0.35 ms at 32², 22.6 → 13.4 ms at 128²; issue 37:
//! 1.27x SciPy's SuperLU on the 32² surface with it).
//!
//! A frame's solve is otherwise the triangular solves and two products
//! around them, and the products were most of it (issue 37: 1.6x SuperLU
//! on the 200- and 1,000-point curves, whose factors have no fill): the
//! fixed values are moved to the right-hand side through the entries that
//! couple them to free unknowns only (kept at factoring), and the residual
//! product runs one right-hand side at a time with its column's own sum in
//! a register. Both give the bits the full products gave (a test says so).
//! Curve frames went from 41 to 17 µs (600 unknowns), the 32² surface's
//! from 316 to 212 µs.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::StylingError;

/// A symmetric sparse matrix in lower-triangle CSC form with a fixed
/// pattern, assembled by adding entries.
#[derive(Clone, Debug)]
pub struct SymPattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl SymPattern {
    /// The pattern holding the given `(row, col)` pairs (either triangle;
    /// stored as the lower one) plus the whole diagonal.
    pub fn new(n: usize, pairs: impl IntoIterator<Item = (usize, usize)>) -> Self {
        let mut cols: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
        for (r, c) in pairs {
            let (r, c) = if r >= c { (r, c) } else { (c, r) };
            cols[c].push(r);
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for mut col in cols {
            col.sort_unstable();
            col.dedup();
            row_idx.extend(col);
            col_ptr.push(row_idx.len());
        }
        Self {
            n,
            col_ptr,
            row_idx,
        }
    }

    /// Number of rows (and columns).
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored entries (lower triangle with diagonal).
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Column pointers of the lower triangle.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row indices of the lower triangle.
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// Index into the value array of entry `(r, c)`, if stored.
    pub fn slot(&self, r: usize, c: usize) -> Option<usize> {
        let (r, c) = if r >= c { (r, c) } else { (c, r) };
        let rows = &self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]];
        rows.binary_search(&r).ok().map(|k| self.col_ptr[c] + k)
    }

    /// `y = A x` for the symmetric matrix with `values` on this pattern,
    /// for `k` right-hand sides stored column-major.
    pub fn mul(&self, values: &[f64], x: &[f64], k: usize) -> Vec<f64> {
        let n = self.n;
        let mut y = vec![0.0; n * k];
        for s in 0..k {
            self.mul_one(values, &x[s * n..(s + 1) * n], &mut y[s * n..(s + 1) * n]);
        }
        y
    }

    /// `y += A x` for one right-hand side. Every `y[i]` receives its terms
    /// in the same order as a column-by-column sweep of the full matrix
    /// (column `c`'s own entry `y[c]` kept in a register), so the bits do
    /// not depend on how many right-hand sides are done together.
    fn mul_one(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        for c in 0..self.n {
            let (lo, hi) = (self.col_ptr[c], self.col_ptr[c + 1]);
            let xc = x[c];
            let mut acc = y[c];
            for (&r, &v) in self.row_idx[lo..hi].iter().zip(&values[lo..hi]) {
                if r == c {
                    acc += v * xc;
                } else {
                    y[r] += v * xc;
                    acc += v * x[r];
                }
            }
            y[c] = acc;
        }
    }
}

/// A factorization of `A` restricted to its free unknowns, reusable while
/// the values of `A` and the fixed set do not change.
pub struct FixedSolver {
    pattern: SymPattern,
    symbolic: SymbolicCholesky<usize>,
    /// The full matrix values (before elimination).
    values: Vec<f64>,
    /// The eliminated matrix values (fixed rows/columns cleared).
    reduced: Vec<f64>,
    fixed: Vec<bool>,
    /// The entries of the full matrix that couple a free row to a fixed
    /// column, `(free row, fixed column, value)`, in the order a column
    /// sweep of [`SymPattern::mul`] meets them: moving the fixed values to
    /// the right-hand side needs only these, and summing them in that
    /// order gives the same bits as the full product (the terms it skips
    /// are products with zero, added to a sum that starts at +0).
    couplings: Vec<(usize, usize, f64)>,
    l_values: Vec<f64>,
    /// ‖reduced‖∞ (largest absolute row sum), for the refinement test.
    norm_inf: f64,
    /// How many numeric factorizations were done (for tests and benches).
    pub refactor_count: usize,
    /// Whether `l_values` holds the factors of `values` with `fixed`
    /// eliminated (false after a failed factorization).
    factored: bool,
    /// How many solves needed their refinement step (for tests and
    /// benches).
    pub refinements: std::sync::atomic::AtomicUsize,
}

/// A solve whose normwise backward error is within this many ε is not
/// refined.
const REFINE_ABOVE_EPS: f64 = 16.0;

impl std::fmt::Debug for FixedSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FixedSolver")
            .field("n", &self.pattern.n)
            .field("nnz", &self.pattern.nnz())
            .field("refactor_count", &self.refactor_count)
            .finish()
    }
}

impl FixedSolver {
    /// Symbolic analysis of `pattern` (AMD ordering). Done once per pattern.
    pub fn new(pattern: SymPattern) -> Result<Self, StylingError> {
        let n = pattern.n;
        let sym =
            SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx);
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Lower,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .map_err(|_| StylingError::Solver("symbolic factorization failed".into()))?;
        let l_len = symbolic.len_val();
        let nnz = pattern.nnz();
        Ok(Self {
            pattern,
            symbolic,
            values: vec![0.0; nnz],
            reduced: vec![0.0; nnz],
            fixed: vec![false; n],
            couplings: Vec::new(),
            l_values: vec![0.0; l_len],
            norm_inf: 0.0,
            refactor_count: 0,
            factored: false,
            refinements: std::sync::atomic::AtomicUsize::new(0),
        })
    }

    /// The factor's kind and size, for benches: `supernodal`/`simplicial`,
    /// the number of stored factor entries, and how many solves so far
    /// needed their refinement step.
    pub fn describe(&self) -> String {
        let kind = match self.symbolic.raw() {
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Simplicial(_) => "simplicial",
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(_) => "supernodal",
        };
        format!(
            "{kind} LDLT, {} factor entries, {} solves refined",
            self.symbolic.len_val(),
            self.refinements.load(std::sync::atomic::Ordering::Relaxed)
        )
    }

    /// The pattern.
    pub fn pattern(&self) -> &SymPattern {
        &self.pattern
    }

    /// The full (uneliminated) matrix values last factored.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The eliminated matrix last factored (fixed rows and columns cleared,
    /// unit diagonal there), on the pattern.
    pub fn reduced(&self) -> &[f64] {
        &self.reduced
    }

    /// Whether the factorization already holds these values and fixed set.
    pub fn is_current(&self, values: &[f64], fixed: &[bool]) -> bool {
        self.factored && self.values == values && self.fixed == fixed
    }

    /// Numeric LDLᵀ of `values` with the unknowns in `fixed` eliminated.
    /// Skipped when nothing changed since the last call.
    pub fn factor(&mut self, values: &[f64], fixed: &[bool]) -> Result<(), StylingError> {
        if values.len() != self.pattern.nnz() || fixed.len() != self.pattern.n {
            return Err(StylingError::Solver("matrix size mismatch".into()));
        }
        if self.is_current(values, fixed) {
            return Ok(());
        }
        if values.iter().any(|v| !v.is_finite()) {
            return Err(StylingError::Solver("non-finite energy matrix".into()));
        }
        // Until the factorization below succeeds, nothing is current (a
        // failed one must not be taken for these values next time).
        self.factored = false;
        self.values.copy_from_slice(values);
        self.fixed.copy_from_slice(fixed);
        let p = &self.pattern;
        self.couplings.clear();
        for c in 0..p.n {
            for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                let r = p.row_idx[k];
                if fixed[c] && !fixed[r] {
                    self.couplings.push((r, c, values[k]));
                }
                if r != c && fixed[r] && !fixed[c] {
                    self.couplings.push((c, r, values[k]));
                }
            }
        }
        for c in 0..p.n {
            for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                let r = p.row_idx[k];
                self.reduced[k] = if fixed[r] || fixed[c] {
                    if r == c {
                        1.0
                    } else {
                        0.0
                    }
                } else {
                    values[k]
                };
            }
        }
        let n = p.n;
        let mut row_sums = vec![0.0f64; n];
        for c in 0..n {
            for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                let (r, v) = (p.row_idx[k], self.reduced[k].abs());
                row_sums[r] += v;
                if r != c {
                    row_sums[c] += v;
                }
            }
        }
        self.norm_inf = row_sums.iter().fold(0.0, |m, &v| m.max(v));
        let a = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &p.col_ptr, None, &p.row_idx),
            &self.reduced,
        );
        let par = Par::Seq;
        let mut mem = MemBuffer::new(
            self.symbolic
                .factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
        );
        self.symbolic
            .factorize_numeric_ldlt::<f64>(
                &mut self.l_values,
                a,
                Side::Lower,
                LdltRegularization::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|_| StylingError::Solver("singular energy matrix (zero pivot)".into()))?;
        self.refactor_count += 1;
        self.factored = true;
        Ok(())
    }

    /// The reduced system's right-hand side: the fixed values moved over,
    /// `b_f = rhs_f - A_fc e` on the free rows, `b_c = e` on the fixed
    /// ones (`k` columns, column-major). Only the coupling entries are
    /// visited, not the whole matrix.
    fn eliminated_rhs(&self, rhs: &[f64], fixed_values: &[f64], k: usize) -> Vec<f64> {
        let n = self.pattern.n;
        let mut b = vec![0.0; n * k];
        for s in 0..k {
            let (b, rhs, e) = (
                &mut b[s * n..(s + 1) * n],
                &rhs[s * n..(s + 1) * n],
                &fixed_values[s * n..(s + 1) * n],
            );
            for &(i, j, v) in &self.couplings {
                b[i] += v * e[j];
            }
            for i in 0..n {
                b[i] = if self.fixed[i] { e[i] } else { rhs[i] - b[i] };
            }
        }
        b
    }

    fn solve_raw(&self, rhs: &mut [f64], k: usize) {
        let n = self.pattern.n;
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, Par::Seq));
        let ldlt = LdltRef::<usize, f64>::new(&self.symbolic, &self.l_values);
        ldlt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, k),
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }

    /// Solves `A x = rhs` with `x[i] = fixed_values[i]` for fixed `i`
    /// (exactly), for `k` right-hand sides stored column-major (`n * k`).
    /// `rhs` entries of fixed unknowns are ignored.
    pub fn solve(
        &self,
        rhs: &[f64],
        fixed_values: &[f64],
        k: usize,
    ) -> Result<Vec<f64>, StylingError> {
        let n = self.pattern.n;
        if !self.factored {
            return Err(StylingError::Solver(
                "no factorization to solve with (none yet, or the last failed)".into(),
            ));
        }
        if rhs.len() != n * k || fixed_values.len() != n * k {
            return Err(StylingError::Solver("right-hand side size mismatch".into()));
        }
        let b = self.eliminated_rhs(rhs, fixed_values, k);
        let mut x = b.clone();
        self.solve_raw(&mut x, k);
        // One step of iterative refinement on the reduced system, unless
        // every right-hand side's residual is already at rounding level.
        let ax = self.pattern.mul(&self.reduced, &x, k);
        let mut r: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
        let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let stable = (0..k).all(|s| {
            let col = s * n..(s + 1) * n;
            max_abs(&r[col.clone()])
                <= REFINE_ABOVE_EPS
                    * f64::EPSILON
                    * (self.norm_inf * max_abs(&x[col.clone()]) + max_abs(&b[col]))
        });
        if !stable {
            self.refinements
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            self.solve_raw(&mut r, k);
            for (xi, ri) in x.iter_mut().zip(&r) {
                *xi += ri;
            }
        }
        for s in 0..k {
            for i in 0..n {
                if self.fixed[i] {
                    x[s * n + i] = b[s * n + i];
                }
            }
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(StylingError::Solver(
                "solve produced non-finite values".into(),
            ));
        }
        Ok(x)
    }
}

#[cfg(test)]
mod tests {
    use super::{FixedSolver, SymPattern};

    /// A banded pattern with a cyclic corner, and values that are
    /// diagonally dominant (so positive definite) with some exact zeros.
    fn banded(n: usize) -> (SymPattern, Vec<f64>) {
        let mut pairs = Vec::new();
        for i in 0..n {
            for d in 1..5 {
                if i + d < n {
                    pairs.push((i + d, i));
                }
            }
        }
        pairs.extend([(n - 1, 0), (n - 2, 1)]);
        let p = SymPattern::new(n, pairs);
        let mut values = vec![0.0; p.nnz()];
        for c in 0..n {
            for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                let r = p.row_idx()[k];
                values[k] = if r == c {
                    20.0 + (c % 7) as f64
                } else if (r * 31 + c).is_multiple_of(5) {
                    0.0
                } else {
                    ((r * 17 + c * 13) % 11) as f64 / 7.0 - 0.7
                };
            }
        }
        (p, values)
    }

    /// The product as a column sweep over all `k` columns at once: the
    /// order every entry of `y` receives its terms in.
    fn sweep(p: &SymPattern, values: &[f64], x: &[f64], k: usize) -> Vec<f64> {
        let n = p.n();
        let mut y = vec![0.0; n * k];
        for c in 0..n {
            for q in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                let r = p.row_idx()[q];
                for s in 0..k {
                    y[s * n + r] += values[q] * x[s * n + c];
                    if r != c {
                        y[s * n + c] += values[q] * x[s * n + r];
                    }
                }
            }
        }
        y
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// A factorization that failed is not taken for current: the same
    /// values factored again fail again, and nothing solves with the
    /// half-written factors (found by the review of issue 37's change).
    #[test]
    fn a_failed_factorization_is_never_current() {
        let n = 12;
        let (p, values) = banded(n);
        let fixed = vec![false; n];
        let mut solver = FixedSolver::new(p.clone()).expect("symbolic");
        solver.factor(&values, &fixed).expect("factor");
        let rhs = vec![1.0; n];
        assert!(solver.solve(&rhs, &rhs, 1).is_ok());
        // Unknown 5 uncoupled and with a zero diagonal: a zero pivot.
        let mut singular = values.clone();
        for c in 0..n {
            for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                if p.row_idx()[k] == 5 || c == 5 {
                    singular[k] = 0.0;
                }
            }
        }
        for _ in 0..2 {
            assert!(solver.factor(&singular, &fixed).is_err());
            assert!(solver.solve(&rhs, &rhs, 1).is_err());
        }
        solver.factor(&values, &fixed).expect("factor again");
        assert!(solver.solve(&rhs, &rhs, 1).is_ok());
    }

    /// The product one column at a time gives the sweep's bits, and moving
    /// fixed values over through the coupling entries alone gives the bits
    /// of the full product with the free entries zeroed.
    #[test]
    fn products_keep_the_full_sweeps_bits() {
        let n = 37;
        let (p, values) = banded(n);
        let k = 3;
        let x: Vec<f64> = (0..n * k)
            .map(|i| ((i * 7919) % 101) as f64 / 13.0 - 3.5)
            .collect();
        assert_eq!(
            bits(&p.mul(&values, &x, k)),
            bits(&sweep(&p, &values, &x, k))
        );
        let fixed: Vec<bool> = (0..n).map(|i| i < 4 || i % 9 == 5 || i == n - 1).collect();
        let mut solver = FixedSolver::new(p.clone()).expect("symbolic");
        solver.factor(&values, &fixed).expect("factor");
        let rhs: Vec<f64> = (0..n * k).map(|i| ((i * 31) % 17) as f64 - 8.0).collect();
        let b = solver.eliminated_rhs(&rhs, &x, k);
        let e: Vec<f64> = (0..n * k)
            .map(|i| if fixed[i % n] { x[i] } else { 0.0 })
            .collect();
        let ae = sweep(&p, &values, &e, k);
        let want: Vec<f64> = (0..n * k)
            .map(|i| if fixed[i % n] { e[i] } else { rhs[i] - ae[i] })
            .collect();
        assert_eq!(bits(&b), bits(&want));
        let sol = solver.solve(&rhs, &x, k).expect("solve");
        let res = p.mul(&values, &sol, k);
        for i in (0..n * k).filter(|i| !fixed[i % n]) {
            assert!(
                (res[i] - rhs[i]).abs() < 1e-12,
                "row {i}: {} vs {}",
                res[i],
                rhs[i]
            );
        }
        for i in (0..n * k).filter(|i| fixed[i % n]) {
            assert_eq!(sol[i], x[i]);
        }
    }

    /// The lookup finds every stored entry and nothing else, on banded
    /// columns, columns with gaps and a cyclic corner.
    #[test]
    fn slot_finds_exactly_the_stored_entries() {
        let n = 40;
        let mut pairs = Vec::new();
        for i in 0..n {
            for d in 1..4 {
                if i + d < n && (i % 7 != 3 || d != 2) {
                    pairs.push((i + d, i));
                }
            }
        }
        pairs.extend([(n - 1, 0), (n - 2, 0), (n - 1, 1), (20, 5)]);
        let p = SymPattern::new(n, pairs.iter().copied());
        let mut seen = std::collections::BTreeSet::new();
        for r in 0..n {
            for c in 0..n {
                let (lo, hi) = if r >= c { (r, c) } else { (c, r) };
                let stored = lo == hi || pairs.contains(&(lo, hi));
                let slot = p.slot(r, c);
                assert_eq!(slot.is_some(), stored, "({r}, {c})");
                if let Some(k) = slot {
                    assert_eq!(p.row_idx()[k], lo, "({r}, {c})");
                    assert!(p.col_ptr()[hi] <= k && k < p.col_ptr()[hi + 1]);
                    if r >= c {
                        assert!(seen.insert(k));
                    }
                }
            }
        }
        assert_eq!(seen.len(), p.nnz());
    }
}
