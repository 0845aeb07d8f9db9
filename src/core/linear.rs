//! The symmetric sparse linear solve of each Newton iteration: a pattern built once per mesh, the
//! symbolic Cholesky analysis (fill-reducing ordering applied to the pattern itself, elimination
//! tree, supernodes) done once on it, and a numeric `LLᵀ` factorization per iteration into reused
//! storage. When the tangent is not
//! positive definite, the factorization is retried on `K + δ·diag(K)` with growing `δ`.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::SupernodalThreshold;
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

    pub fn nnz(&self) -> usize {
        self.row_idx.len()
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

/// The scratch memory a numeric factorization and a one-column solve need at `par`.
fn scratch(symbolic: &SymbolicCholesky<usize>, par: Par) -> faer::dyn_stack::StackReq {
    symbolic
        .factorize_numeric_llt_scratch::<f64>(par, Default::default())
        .or(symbolic.solve_in_place_scratch::<f64>(1, par))
}

/// Runs `f` on a worker of rayon's pool when `par` is parallel. faer's supernodal factorization
/// visits the supernodes in order and splits each one's dense kernels over the threads: called
/// from outside the pool, every split is a hand-over to the pool and back, which made the open
/// box at fine 1.7× slower on two threads than on one (14.3 s against 8.5 s); from inside, the
/// same (8.6 s).
fn in_pool<R: Send>(par: Par, f: impl FnOnce() -> R + Send) -> R {
    match par {
        Par::Seq => f(),
        _ => rayon::scope(|_| f()),
    }
}

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
    /// The factorization's and the solves' parallelism (sequential unless asked).
    par: Par,
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
        // faer's analysis without ordering reads the upper triangle; its supernodal numeric
        // factorization reads the lower one without copying it.
        let upper = UpperPattern::from_couplings(
            n,
            (0..n).flat_map(|c| {
                row_idx[col_ptr[c]..col_ptr[c + 1]]
                    .iter()
                    .map(move |&r| (r, c))
            }),
        );
        let symbolic = factorize_symbolic_cholesky(
            SymbolicSparseColMatRef::new_checked(n, n, &upper.col_ptr, None, &upper.row_idx),
            Side::Upper,
            SymmetricOrdering::Identity,
            // Always supernodal: faer's automatic choice takes the simplicial variant on some of
            // the yarn grids (1,825 and 936 dofs), where it made whole runs 1.6–2× slower.
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .expect("symbolic Cholesky analysis of the permuted pattern");
        let req = scratch(&symbolic, Par::Seq);
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
            par: Par::Seq,
        }
    }

    /// Factorize and solve on up to `threads` threads of rayon's pool (1: sequential). The
    /// supernodal factorization splits the elimination tree's independent branches and the
    /// dense updates of the large supernodes; the result is the same to round-off.
    pub fn set_threads(&mut self, threads: usize) {
        let par = if threads <= 1 {
            Par::Seq
        } else {
            Par::rayon(threads)
        };
        if par != self.par {
            self.par = par;
            self.mem = MemBuffer::new(scratch(&self.symbolic, par));
        }
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

    /// Non-zeros of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    fn factorize(&mut self, values: &[f64]) -> bool {
        let n = self.n;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(sym, values);
        let stack = MemStack::new(&mut self.mem);
        let (symbolic, l_values, par) = (&self.symbolic, &mut self.l_values, self.par);
        in_pool(par, || {
            symbolic
                .factorize_numeric_llt(
                    l_values,
                    a,
                    Side::Lower,
                    LltRegularization::default(),
                    par,
                    stack,
                    Default::default(),
                )
                .is_ok()
        })
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
        let llt = LltRef::new(&self.symbolic, &self.l_values);
        let stack = MemStack::new(&mut self.mem);
        let n = rhs.len();
        let x = MatMut::from_column_major_slice_mut(&mut self.permuted_rhs, n, 1);
        let par = self.par;
        in_pool(par, || {
            llt.solve_in_place_with_conj(Conj::No, x, par, stack)
        });
        for (i, v) in rhs.iter_mut().enumerate() {
            *v = self.permuted_rhs[self.new[i]];
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
        chol.set_threads(2);
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
}
