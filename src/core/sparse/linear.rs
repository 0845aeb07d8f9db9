//! The symmetric sparse linear solve of each Newton iteration: a pattern built once per mesh, the
//! symbolic Cholesky analysis (fill-reducing ordering applied to the pattern itself, elimination
//! tree, supernodes) done once on it, and a numeric `LLᵀ` factorization per iteration into reused
//! storage. On two threads the factorization and its solves are split over two halves of the
//! equations ([`crate::core::sparse::split_cholesky`]). When the tangent is not positive definite, the
//! factorization is retried on `K + δ·diag(K)` with growing `δ`.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::{Conj, MatMut, Par, Side};

use super::pattern;
pub use super::pattern::UpperPattern;
use super::split_cholesky::SplitCholesky;

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
///
/// The fill-reducing ordering (AMD) is applied once, to the pattern: the matrix is stored as the
/// lower triangle of `P K Pᵀ` in compressed columns, and [`SparseCholesky::slot`] tells the
/// assembly where each entry goes. faer then factorizes the stored matrix as it is, instead of
/// permuting a copy of it at every factorization.
pub struct SparseCholesky {
    /// Equations.
    n: usize,
    /// `new[i]`: the position of the caller's equation `i` in the factorized matrix.
    new: Vec<usize>,
    /// The lower triangle of `P K Pᵀ`, compressed columns (rows sorted).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    shifted: Vec<f64>,
    diag: Vec<usize>,
    permuted_rhs: Vec<f64>,
    mem: MemBuffer,
    /// On two threads: the factorization split over two halves of the equations and their
    /// separator (`None`: one thread, or no fair split).
    split: Option<Box<SplitCholesky>>,
}

impl SparseCholesky {
    /// Symbolic analysis of `pattern` (done once per mesh): the AMD ordering, the permuted
    /// pattern and its elimination tree and supernodes.
    pub fn new(pattern: UpperPattern) -> Self {
        let n = pattern.n;
        let sym =
            SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx);
        let ordering = factorize_symbolic_cholesky(
            sym,
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .expect("symbolic Cholesky analysis of a valid pattern");
        let new: Vec<usize> = match ordering.perm() {
            Some(perm) => perm.arrays().1.to_vec(),
            None => (0..n).collect(),
        };
        // The lower triangle of the permuted matrix: entry (r, c) of the caller's upper triangle
        // lands at (max, min) of (new[r], new[c]).
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for c in 0..n {
            for &r in &pattern.row_idx[pattern.col_ptr[c]..pattern.col_ptr[c + 1]] {
                let (a, b) = (new[r], new[c]);
                cols[a.min(b)].push(a.max(b));
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(pattern.nnz());
        col_ptr.push(0);
        for mut col in cols {
            col.sort_unstable();
            row_idx.extend_from_slice(&col);
            col_ptr.push(row_idx.len());
        }
        let symbolic = pattern::analyse(&col_ptr, &row_idx);
        let req = pattern::scratch(&symbolic);
        let l_values = vec![0.0; symbolic.len_val()];
        // The diagonal leads each column of a lower triangle.
        let diag = col_ptr[..n].to_vec();
        SparseCholesky {
            shifted: vec![0.0; row_idx.len()],
            permuted_rhs: vec![0.0; n],
            n,
            new,
            col_ptr,
            row_idx,
            symbolic,
            l_values,
            diag,
            mem: MemBuffer::new(req),
            split: None,
        }
    }

    /// Factorize and solve on two threads of rayon's pool when `threads` ≥ 2 (1: sequential):
    /// the equations split over two halves and their separator ([`SplitCholesky`]), each half
    /// on its own thread. When the pattern has no fair split, one thread. The result is the
    /// same to round-off.
    ///
    /// `key`, one value per equation (the caller's numbering), places the cut: its median, e.g.
    /// a coordinate of each equation's node; without it the cut follows the matrix's graph.
    pub fn set_threads(&mut self, threads: usize, key: Option<&[f64]>) {
        if threads <= 1 {
            self.split = None;
        } else if self.split.is_none() {
            let key = key.filter(|k| k.len() == self.n).map(|k| {
                let mut permuted = vec![0.0; self.n];
                for (i, &v) in k.iter().enumerate() {
                    permuted[self.new[i]] = v;
                }
                permuted
            });
            self.split =
                SplitCholesky::new(&self.col_ptr, &self.row_idx, key.as_deref()).map(Box::new);
        }
        // One factor's storage at a time: the split's halves, or the whole.
        let whole = if self.split.is_some() {
            0
        } else {
            self.symbolic.len_val()
        };
        self.l_values.resize(whole, 0.0);
        self.l_values.shrink_to_fit();
    }

    /// Equations.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Stored entries: the length of the value array the assembly fills.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Where the entry `(row, col)` (the caller's equations, either order) is stored, if it is
    /// in the pattern.
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let (a, b) = (self.new[row], self.new[col]);
        let (r, c) = (a.max(b), a.min(b));
        let range = self.col_ptr[c]..self.col_ptr[c + 1];
        self.row_idx[range.clone()]
            .binary_search(&r)
            .ok()
            .map(|p| range.start + p)
    }

    /// `y = K x` in the caller's numbering, for `K` stored in `values`; `scratch` holds two
    /// vectors of the permuted numbering (resized as needed).
    pub fn mul(&self, values: &[f64], x: &[f64], y: &mut [f64], scratch: &mut Vec<f64>) {
        let n = self.n;
        scratch.clear();
        scratch.resize(2 * n, 0.0);
        let (xp, yp) = scratch.split_at_mut(n);
        for (i, &v) in x.iter().enumerate() {
            xp[self.new[i]] = v;
        }
        for c in 0..n {
            let xc = xp[c];
            let mut acc = 0.0;
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                let r = self.row_idx[p];
                let v = values[p];
                if r != c {
                    yp[r] += v * xc;
                    acc += v * xp[r];
                } else {
                    acc += v * xc;
                }
            }
            yp[c] += acc;
        }
        for (i, v) in y.iter_mut().enumerate() {
            *v = yp[self.new[i]];
        }
    }

    /// The largest absolute diagonal entry of `values`.
    pub fn diagonal_max(&self, values: &[f64]) -> f64 {
        self.diag
            .iter()
            .map(|&s| values[s].abs())
            .fold(0.0f64, f64::max)
    }

    fn factorize(&mut self, values: &[f64]) -> bool {
        if let Some(split) = self.split.as_mut() {
            return split.factor(values);
        }
        let stack = MemStack::new(&mut self.mem);
        let pattern = (&self.col_ptr[..], &self.row_idx[..]);
        pattern::factorize(&self.symbolic, pattern, values, &mut self.l_values, stack)
    }

    /// Factorizes `values`; on a non-positive pivot retries on `K + δ diag(K)` (plus a floor for
    /// zero diagonals) with `δ = 1e-10, 1e-8, …, 1`. [`SparseCholesky::solve_in_place`] then
    /// solves with it.
    pub fn factor(&mut self, values: &[f64]) -> Result<SolveInfo, NotFactorizable> {
        if self.factorize(values) {
            return Ok(SolveInfo { shift: 0.0 });
        }
        let max_diag = self.diagonal_max(values).max(f64::MIN_POSITIVE);
        for k in 0..6 {
            let shift = 10f64.powi(-10 + 2 * k);
            self.shifted.copy_from_slice(values);
            for &s in &self.diag {
                let d = self.shifted[s].abs();
                self.shifted[s] += shift * d.max(1e-3 * max_diag);
            }
            let shifted = std::mem::take(&mut self.shifted);
            let ok = self.factorize(&shifted);
            self.shifted = shifted;
            if ok {
                return Ok(SolveInfo { shift });
            }
        }
        Err(NotFactorizable)
    }

    /// [`SparseCholesky::factor`], then the solve in place.
    pub fn factor_solve(
        &mut self,
        values: &[f64],
        rhs: &mut [f64],
    ) -> Result<SolveInfo, NotFactorizable> {
        let info = self.factor(values)?;
        self.solve_in_place(rhs);
        Ok(info)
    }

    /// Solves with the last factorization, in place.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        for (i, &v) in rhs.iter().enumerate() {
            self.permuted_rhs[self.new[i]] = v;
        }
        if let Some(split) = self.split.as_mut() {
            split.solve_in_place(&mut self.permuted_rhs);
        } else {
            let llt = LltRef::new(&self.symbolic, &self.l_values);
            let stack = MemStack::new(&mut self.mem);
            let n = rhs.len();
            let x = MatMut::from_column_major_slice_mut(&mut self.permuted_rhs, n, 1);
            llt.solve_in_place_with_conj(Conj::No, x, Par::Seq, stack);
        }
        for (i, v) in rhs.iter_mut().enumerate() {
            *v = self.permuted_rhs[self.new[i]];
        }
    }
}

/// What the tests measure of a factorization: the split's separator, the entries it stores.
#[cfg(test)]
impl SparseCholesky {
    /// Equations on the separator of the two-thread split, if there is one.
    fn split_separator(&self) -> Option<usize> {
        self.split.as_ref().map(|s| s.separator_len())
    }

    /// Entries the Cholesky factorization stores: the whole factor's non-zeros, or on two
    /// threads the halves' factors and the separator's dense blocks (1.29–1.35 times as many on
    /// the box).
    pub(crate) fn factor_nnz(&self) -> usize {
        match &self.split {
            Some(split) => split.factor_entries(),
            None => self.symbolic.len_val(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 5-point Laplacian plus the identity on an `m × m` grid: its upper pattern and values
    /// in the solver's storage.
    fn grid_matrix(m: usize) -> (SparseCholesky, Vec<f64>) {
        let n = m * m;
        let id = |i: usize, j: usize| i * m + j;
        let mut pairs = Vec::new();
        for i in 0..m {
            for j in 0..m {
                if i + 1 < m {
                    pairs.push((id(i, j), id(i + 1, j)));
                }
                if j + 1 < m {
                    pairs.push((id(i, j), id(i, j + 1)));
                }
            }
        }
        let chol = SparseCholesky::new(UpperPattern::from_couplings(n, pairs.iter().copied()));
        let mut values = vec![0.0; chol.nnz()];
        for k in 0..n {
            values[chol.slot(k, k).unwrap()] = 5.0;
        }
        for &(a, b) in &pairs {
            values[chol.slot(a, b).unwrap()] = -1.0;
        }
        (chol, values)
    }

    fn max_abs_difference(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn two_threads_solve_the_system_as_one_does() {
        let (mut chol, values) = grid_matrix(40);
        let n = chol.n();
        let rhs: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut one = rhs.clone();
        chol.factor_solve(&values, &mut one).unwrap();
        chol.set_threads(2, None);
        let mut two = rhs.clone();
        chol.factor_solve(&values, &mut two).unwrap();
        // K x = b holds for both, and they agree to round-off.
        let mut kx = vec![0.0; n];
        let mut scratch = Vec::new();
        chol.mul(&values, &two, &mut kx, &mut scratch);
        let residual = max_abs_difference(&kx, &rhs);
        assert!(residual < 1e-10, "{residual}");
        let apart = max_abs_difference(&one, &two);
        assert!(apart < 1e-12, "{apart}");
    }

    /// A membrane-like matrix: an `m × m` grid of nodes with three equations each, every pair
    /// of equations of a quad's four nodes coupled, symmetric and diagonally dominant. Returns
    /// the solver, its values and each equation's node's x.
    fn quad_grid(m: usize) -> (SparseCholesky, Vec<f64>, Vec<f64>) {
        let node = |i: usize, j: usize| i * m + j;
        let mut quads = Vec::new();
        for i in 0..m - 1 {
            for j in 0..m - 1 {
                quads.push([
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                ]);
            }
        }
        let mut pairs = Vec::new();
        for q in &quads {
            let dofs: Vec<usize> = q
                .iter()
                .flat_map(|&n| (0..3).map(move |a| 3 * n + a))
                .collect();
            for &a in &dofs {
                pairs.extend(dofs.iter().map(|&b| (a, b)));
            }
        }
        let n = 3 * m * m;
        let chol = SparseCholesky::new(UpperPattern::from_couplings(n, pairs.iter().copied()));
        let mut values = vec![0.0; chol.nnz()];
        for &(a, b) in pairs.iter().filter(|(a, b)| a < b) {
            let v = -0.01 * (1.0 + ((a * 31 + b * 17) % 7) as f64);
            values[chol.slot(a, b).unwrap()] += v;
        }
        for k in 0..n {
            values[chol.slot(k, k).unwrap()] = 10.0 + (k % 5) as f64;
        }
        let x = (0..n).map(|k| ((k / 3) / m) as f64).collect();
        (chol, values, x)
    }

    fn solve(chol: &mut SparseCholesky, values: &[f64], rhs: &[f64]) -> Vec<f64> {
        let mut x = rhs.to_vec();
        chol.factor_solve(values, &mut x).unwrap();
        x
    }

    #[test]
    fn two_halves_and_their_separator_solve_as_one_factorization_does() {
        let (mut chol, values, key) = quad_grid(30);
        let n = chol.n();
        let rhs: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let one = solve(&mut chol, &values, &rhs);
        for (key, most) in [(Some(&key[..]), 3 * 30), (None, 6 * 30)] {
            let (mut split, _, _) = quad_grid(30);
            split.set_threads(2, key);
            let ns = split.split_separator().expect("a fair split");
            // The cut along x is one line of nodes; the graph's level an L across the grid.
            assert!(ns <= most, "separator of {ns} equations");
            let two = solve(&mut split, &values, &rhs);
            // K x = b to round-off, and the same x as one factorization.
            let mut kx = vec![0.0; n];
            chol.mul(&values, &two, &mut kx, &mut Vec::new());
            let residual = kx.iter().zip(&rhs).map(|(a, b)| (a - b).abs());
            assert!(residual.fold(0.0, f64::max) < 1e-10);
            let apart = one.iter().zip(&two).map(|(a, b)| (a - b).abs());
            assert!(apart.fold(0.0, f64::max) < 1e-12);
        }
    }

    #[test]
    fn a_matrix_that_is_not_positive_definite_is_shifted_as_by_one_thread() {
        let (mut chol, mut values, key) = quad_grid(24);
        // Two equations coupled more strongly than their diagonals hold: indefinite.
        values[chol.slot(100, 103).unwrap()] = 20.0;
        let mut rhs = vec![1.0; chol.n()];
        let one = chol.factor_solve(&values, &mut rhs).unwrap();
        chol.set_threads(2, Some(&key));
        assert!(chol.split_separator().is_some());
        let mut rhs = vec![1.0; chol.n()];
        let two = chol.factor_solve(&values, &mut rhs).unwrap();
        assert!(one.shift > 0.0);
        assert_eq!(one.shift, two.shift);
    }

    #[test]
    fn a_small_or_unsplittable_matrix_stays_on_one_thread() {
        let (mut chol, _, key) = quad_grid(8);
        chol.set_threads(2, Some(&key));
        assert_eq!(chol.split_separator(), None);
        // A dense block: every equation coupled to every other has no small separator.
        let n = 300;
        let pairs = (0..n).flat_map(|a| (0..n).map(move |b| (a, b)));
        let mut dense = SparseCholesky::new(UpperPattern::from_couplings(n, pairs));
        dense.set_threads(2, None);
        assert_eq!(dense.split_separator(), None);
    }
}
