//! The pattern of a symmetric sparse matrix (its upper triangle in compressed columns), and
//! faer's supernodal Cholesky of a lower triangle stored in the order it is given: the analysis
//! once per pattern, the numeric factorization per matrix.

use faer::dyn_stack::MemStack;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Par, Side};

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

/// The symbolic analysis of the lower triangle `col_ptr`, `row_idx` (compressed columns, rows
/// sorted) in its own order, supernodal.
pub fn analyse(col_ptr: &[usize], row_idx: &[usize]) -> SymbolicCholesky<usize> {
    let n = col_ptr.len() - 1;
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
    factorize_symbolic_cholesky(
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
    .expect("symbolic Cholesky analysis of a valid pattern")
}

/// The numeric factorization into `l_values` of the lower triangle `values` on the pattern
/// `symbolic` was analysed from; false when the matrix is not positive definite.
pub fn factorize(
    symbolic: &SymbolicCholesky<usize>,
    (col_ptr, row_idx): (&[usize], &[usize]),
    values: &[f64],
    l_values: &mut [f64],
    stack: &mut MemStack,
) -> bool {
    let n = col_ptr.len() - 1;
    let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let a = SparseColMatRef::new(sym, values);
    (symbolic)
        .factorize_numeric_llt(
            l_values,
            a,
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            stack,
            Default::default(),
        )
        .is_ok()
}

/// The scratch memory a numeric factorization on `symbolic` and a one-column solve need.
pub fn scratch(symbolic: &SymbolicCholesky<usize>) -> faer::dyn_stack::StackReq {
    symbolic
        .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
        .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
}
