//! The symmetric sparse linear solve of each Newton iteration: a pattern built once per mesh, the
//! symbolic Cholesky analysis (fill-reducing ordering, elimination tree) done once on it, and a
//! numeric `LLᵀ` factorization per iteration into reused storage. When the tangent is not
//! positive definite, the factorization is retried on `K + δ·diag(K)` with growing `δ`.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// The upper triangle of a symmetric matrix in compressed sparse columns (rows sorted).
#[derive(Clone, Debug)]
pub struct UpperPattern {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
}

impl UpperPattern {
    /// From a list of `(row, col)` couplings (either order; duplicates allowed). The diagonal is
    /// always included.
    pub fn from_couplings(n: usize, couplings: impl Iterator<Item = (usize, usize)>) -> Self {
        let mut cols: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
        for (i, j) in couplings {
            let (r, c) = if i <= j { (i, j) } else { (j, i) };
            cols[c].push(r);
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for mut c in cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(&c);
            col_ptr.push(row_idx.len());
        }
        UpperPattern {
            n,
            col_ptr,
            row_idx,
        }
    }

    /// The position of `(row, col)` (row ≤ col) in the value array.
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let (r, c) = if row <= col { (row, col) } else { (col, row) };
        let range = self.col_ptr[c]..self.col_ptr[c + 1];
        self.row_idx[range.clone()]
            .binary_search(&r)
            .ok()
            .map(|p| range.start + p)
    }

    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// The position of each diagonal entry.
    pub fn diagonal_slots(&self) -> Vec<usize> {
        (0..self.n).map(|i| self.col_ptr[i + 1] - 1).collect()
    }

    /// `y = A x` for the symmetric matrix stored by its upper triangle in `values`.
    pub fn mul(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for c in 0..self.n {
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                let r = self.row_idx[p];
                y[r] += values[p] * x[c];
                if r != c {
                    y[c] += values[p] * x[r];
                }
            }
        }
    }
}

/// How a solve went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveInfo {
    /// The diagonal shift `δ` needed to factorize (0 when the tangent was positive definite).
    pub shift: f64,
}

/// The tangent could not be factorized even regularised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NotFactorizable;

/// A sparse Cholesky solver bound to one pattern.
pub struct SparseCholesky {
    pattern: UpperPattern,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    shifted: Vec<f64>,
    diag: Vec<usize>,
    mem: MemBuffer,
}

impl SparseCholesky {
    /// Symbolic analysis of `pattern` (done once per mesh).
    pub fn new(pattern: UpperPattern) -> Self {
        let sym = SymbolicSparseColMatRef::new_checked(
            pattern.n,
            pattern.n,
            &pattern.col_ptr,
            None,
            &pattern.row_idx,
        );
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .expect("symbolic Cholesky analysis of a valid pattern");
        let par = Par::Seq;
        let req = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let l_values = vec![0.0; symbolic.len_val()];
        let diag = pattern.diagonal_slots();
        SparseCholesky {
            shifted: vec![0.0; pattern.nnz()],
            pattern,
            symbolic,
            l_values,
            diag,
            mem: MemBuffer::new(req),
        }
    }

    pub fn pattern(&self) -> &UpperPattern {
        &self.pattern
    }

    /// Non-zeros of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    fn factorize(&mut self, values: &[f64]) -> bool {
        let p = &self.pattern;
        let sym = SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx);
        let a = SparseColMatRef::new(sym, values);
        let stack = MemStack::new(&mut self.mem);
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                a,
                Side::Upper,
                LltRegularization::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .is_ok()
    }

    /// Factorizes `values` and solves in place; on a non-positive pivot retries on
    /// `K + δ diag(K)` (plus a floor for zero diagonals) with `δ = 1e-10, 1e-8, …, 1`.
    pub fn factor_solve(
        &mut self,
        values: &[f64],
        rhs: &mut [f64],
    ) -> Result<SolveInfo, NotFactorizable> {
        let mut shift = 0.0;
        if !self.factorize(values) {
            let max_diag = self
                .diag
                .iter()
                .map(|&s| values[s].abs())
                .fold(0.0f64, f64::max)
                .max(f64::MIN_POSITIVE);
            let mut ok = false;
            for k in 0..6 {
                shift = 10f64.powi(-10 + 2 * k);
                self.shifted.copy_from_slice(values);
                for &s in &self.diag {
                    let d = self.shifted[s].abs();
                    self.shifted[s] += shift * d.max(1e-3 * max_diag);
                }
                let shifted = std::mem::take(&mut self.shifted);
                ok = self.factorize(&shifted);
                self.shifted = shifted;
                if ok {
                    break;
                }
            }
            if !ok {
                return Err(NotFactorizable);
            }
        }
        self.solve(rhs);
        Ok(SolveInfo { shift })
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        let llt = LltRef::new(&self.symbolic, &self.l_values);
        let stack = MemStack::new(&mut self.mem);
        let n = rhs.len();
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        llt.solve_in_place_with_conj(Conj::No, x, Par::Seq, stack);
    }
}
