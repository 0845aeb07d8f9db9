//! One sparse Cholesky factorization on two threads: the equations split into two halves that
//! share no entry of the matrix and the separator between them (one level of nested
//! dissection), each half factorized on its own thread with the separator ordered last.
//!
//! ```text
//!        ⎡ A₁₁  0   A₁ₛ ⎤      Mᵢ = ⎡ Aᵢᵢ Aᵢₛ ⎤ = Lᵢ Lᵢᵀ  (each on its own thread)
//!   A =  ⎢ 0   A₂₂  A₂ₛ ⎥           ⎣ Aₛᵢ Aₛₛ ⎦
//!        ⎣ Aₛ₁ Aₛ₂  Aₛₛ ⎦      Sᵢ = Aₛₛ − Aₛᵢ Aᵢᵢ⁻¹ Aᵢₛ = Lᵢ,ₛₛ Lᵢ,ₛₛᵀ  (Mᵢ's Schur complement)
//!
//!   S = Aₛₛ − Σ Aₛᵢ Aᵢᵢ⁻¹ Aᵢₛ = S₁ + S₂ − Aₛₛ,   factorized dense
//! ```
//!
//! Each `Mᵢ` is a principal submatrix of `A`, so it is positive definite where `A` is. A solve
//! `A x = b` takes two solves with each `Mᵢ` (on its own thread) and one with `S`:
//! `Mᵢ⁻¹ [bᵢ; 0]` ends in `tᵢ = −Sᵢ⁻¹ cᵢ` with `cᵢ = Aₛᵢ Aᵢᵢ⁻¹ bᵢ`; then `xₛ = S⁻¹(bₛ − c₁ − c₂)`;
//! then `Mᵢ⁻¹ [bᵢ; cᵢ + Sᵢ xₛ] = [xᵢ; xₛ]`.
//!
//! The separator is a level of a breadth-first search over the matrix's graph from a
//! pseudo-peripheral equation: no entry couples the levels before it with those after it.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{
    LltRegularization, cholesky_in_place, cholesky_in_place_scratch,
};
use faer::linalg::matmul::triangular::{BlockStructure, matmul};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::{Accum, ColMut, ColRef, Conj, Mat, MatMut, Par};

use super::pattern::{self, UpperPattern};

/// A split is kept only when the separator has at most this share of the equations.
const SEPARATOR_SHARE: f64 = 0.1;
/// … and each half at least this share.
const HALF_SHARE: f64 = 0.3;

/// Fewer equations than this are not split: one thread solves them faster.
const MIN_EQUATIONS: usize = 256;

/// One half of the split: its interior equations followed by the separator's.
struct Half {
    /// The matrix's equations (the caller's stored numbering) of this half's interior.
    interior: Vec<usize>,
    /// `Mᵢ`'s lower triangle in compressed columns, and where each entry comes from in the
    /// caller's values.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    source: Vec<usize>,
    values: Vec<f64>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    mem: MemBuffer,
    /// `Sᵢ = Lᵢ,ₛₛ Lᵢ,ₛₛᵀ` (lower triangle) of the last factorization, and the `Lᵢ,ₛₛ` it came from.
    schur: Mat<f64>,
    l_ss: Mat<f64>,
    /// One right-hand side over the half (between the passes: `[zᵢ; zₛ]`), and `cᵢ` of the
    /// solve under way.
    rhs: Vec<f64>,
    c: Vec<f64>,
}

/// The factorization split over two threads.
pub struct SplitCholesky {
    separator: Vec<usize>,
    halves: [Half; 2],
    /// `Aₛₛ`'s stored entries: (row, column) in the separator (row ≥ column), and the slot.
    separator_entries: Vec<(usize, usize, usize)>,
    /// `S` and then its dense Cholesky factor (lower triangle).
    schur: Mat<f64>,
    dense_mem: MemBuffer,
}

/// The lower triangle of a symmetric matrix (compressed columns, rows sorted): its adjacency.
fn adjacency(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Vec<Vec<usize>> {
    let mut adj = vec![Vec::new(); n];
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            if r != c {
                adj[c].push(r);
                adj[r].push(c);
            }
        }
    }
    adj
}

/// Breadth-first levels from `start`: each equation's level (`usize::MAX` when unreached) and
/// the number of levels.
fn levels(adj: &[Vec<usize>], start: usize) -> (Vec<usize>, usize) {
    let mut level = vec![usize::MAX; adj.len()];
    let mut front = vec![start];
    level[start] = 0;
    let mut depth = 0;
    while !front.is_empty() {
        depth += 1;
        let mut next = Vec::new();
        for &v in &front {
            for &w in &adj[v] {
                if level[w] == usize::MAX {
                    level[w] = depth;
                    next.push(w);
                }
            }
        }
        front = next;
    }
    (level, depth)
}

/// A pseudo-peripheral equation's levels: restarted from the farthest equation while that
/// deepens the search.
fn peripheral_levels(adj: &[Vec<usize>]) -> (Vec<usize>, usize) {
    let mut best = levels(adj, 0);
    for _ in 0..4 {
        let far = (0..adj.len())
            .filter(|&v| best.0[v] == best.1 - 1)
            .min_by_key(|&v| adj[v].len())
            .unwrap_or(0);
        let next = levels(adj, far);
        if next.1 <= best.1 {
            break;
        }
        best = next;
    }
    best
}

/// Splits the equations: `(interior 1, interior 2, separator)`, or `None` when no cut makes
/// a small separator between two halves of fair size. With `key` (a coordinate of each
/// equation's node), the cut is at its median, the separator the equations before the cut
/// coupled to one after it; without, or when that cut is not fair, a breadth-first level from
/// a pseudo-peripheral equation.
fn partition(adj: &[Vec<usize>], key: Option<&[f64]>) -> Option<[Vec<usize>; 3]> {
    let n = adj.len();
    let parts = |side: Vec<usize>| {
        let mut parts: [Vec<usize>; 3] = Default::default();
        for (v, &p) in side.iter().enumerate() {
            parts[p].push(v);
        }
        let share = |p: &Vec<usize>| p.len() as f64 / n as f64;
        let fair = share(&parts[2]) <= SEPARATOR_SHARE
            && share(&parts[0]) >= HALF_SHARE
            && share(&parts[1]) >= HALF_SHARE;
        fair.then_some(parts)
    };
    let by_key = key.map(|key| {
        let mut sorted = key.to_vec();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[n / 2];
        let left = |v: usize| key[v] < median;
        (0..n)
            .map(|v| match left(v) {
                true if adj[v].iter().any(|&w| !left(w)) => 2,
                true => 0,
                false => 1,
            })
            .collect()
    });
    by_key.and_then(parts).or_else(|| parts(level_sides(adj)))
}

/// Each equation's side (0, 1, or 2 for the separator) of the breadth-first level that halves
/// the equations.
fn level_sides(adj: &[Vec<usize>]) -> Vec<usize> {
    let n = adj.len();
    let (level, depth) = peripheral_levels(adj);
    let mut count = vec![0usize; depth];
    for &l in level.iter().filter(|&&l| l != usize::MAX) {
        count[l] += 1;
    }
    let mut before = 0;
    let mut cut = 0;
    for (l, &c) in count.iter().enumerate() {
        if before + c >= n / 2 {
            cut = l;
            break;
        }
        before += c;
    }
    (level.iter())
        .map(|&l| match l {
            l if l < cut => 0,
            l if l == cut => 2,
            _ => 1,
        })
        .collect()
}

/// `interior` in an approximate-minimum-degree order of its own block of the matrix (lower
/// triangle `col_ptr`, `row_idx`).
fn amd_order(interior: Vec<usize>, col_ptr: &[usize], row_idx: &[usize]) -> Vec<usize> {
    let ni = interior.len();
    let mut local = vec![usize::MAX; col_ptr.len() - 1];
    for (k, &g) in interior.iter().enumerate() {
        local[g] = k;
    }
    let pairs = interior.iter().flat_map(|&c| {
        let local = &local;
        row_idx[col_ptr[c]..col_ptr[c + 1]]
            .iter()
            .filter(move |&&r| local[r] != usize::MAX)
            .map(move |&r| (local[r], local[c]))
    });
    let upper = UpperPattern::from_couplings(ni, pairs);
    let (mut perm, mut perm_inv) = (vec![0usize; ni], vec![0usize; ni]);
    let mut mem = MemBuffer::new(amd::order_scratch::<usize>(ni, upper.nnz()));
    let ordered = amd::order(
        &mut perm,
        &mut perm_inv,
        SymbolicSparseColMatRef::new_checked(ni, ni, &upper.col_ptr, None, &upper.row_idx),
        amd::Control::default(),
        MemStack::new(&mut mem),
    );
    match ordered {
        Ok(_) => perm.iter().map(|&k| interior[k]).collect(),
        Err(_) => interior,
    }
}

/// The supernodal factor with values `l_values` (the halves are always analysed supernodal).
fn supernodal<'a>(
    symbolic: &'a SymbolicCholesky<usize>,
    l_values: &'a [f64],
) -> SupernodalLltRef<'a, usize, f64> {
    let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
        unreachable!("the halves are analysed supernodal")
    };
    SupernodalLltRef::new(sn, l_values)
}

impl Half {
    /// `Mᵢ` over `interior` and `separator` (both in the caller's order), from the caller's
    /// lower triangle.
    fn new(
        interior: Vec<usize>,
        separator: &[usize],
        col_ptr: &[usize],
        row_idx: &[usize],
    ) -> Half {
        let n_total = col_ptr.len() - 1;
        let interior = amd_order(interior, col_ptr, row_idx);
        let mut local = vec![usize::MAX; n_total];
        for (k, &g) in interior.iter().chain(separator).enumerate() {
            local[g] = k;
        }
        let n = interior.len() + separator.len();
        let mut cols: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for c in 0..n_total {
            for p in col_ptr[c]..col_ptr[c + 1] {
                let (lr, lc) = (local[row_idx[p]], local[c]);
                if lr != usize::MAX && lc != usize::MAX {
                    cols[lr.min(lc)].push((lr.max(lc), p));
                }
            }
        }
        let (mut ptr, mut rows, mut source) = (vec![0], Vec::new(), Vec::new());
        for mut col in cols {
            col.sort_unstable();
            rows.extend(col.iter().map(|e| e.0));
            source.extend(col.iter().map(|e| e.1));
            ptr.push(rows.len());
        }
        let symbolic = pattern::analyse(&ptr, &rows);
        let ns = separator.len();
        Half {
            mem: MemBuffer::new(pattern::scratch(&symbolic)),
            l_values: vec![0.0; symbolic.len_val()],
            values: vec![0.0; rows.len()],
            interior,
            col_ptr: ptr,
            row_idx: rows,
            source,
            symbolic,
            schur: Mat::zeros(ns, ns),
            l_ss: Mat::zeros(ns, ns),
            rhs: vec![0.0; n],
            c: vec![0.0; ns],
        }
    }

    fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Factorizes `Mᵢ` from the caller's `values` and forms `Sᵢ`; false when `Mᵢ` is not
    /// positive definite.
    fn factor(&mut self, values: &[f64]) -> bool {
        for (v, &p) in self.values.iter_mut().zip(&self.source) {
            *v = values[p];
        }
        let stack = MemStack::new(&mut self.mem);
        let stored = (&self.col_ptr[..], &self.row_idx[..]);
        if !pattern::factorize(
            &self.symbolic,
            stored,
            &self.values,
            &mut self.l_values,
            stack,
        ) {
            return false;
        }
        self.gather_l_ss();
        matmul(
            self.schur.as_mut(),
            BlockStructure::TriangularLower,
            Accum::Replace,
            self.l_ss.as_ref(),
            BlockStructure::TriangularLower,
            self.l_ss.as_ref().transpose(),
            BlockStructure::TriangularUpper,
            1.0,
            Par::Seq,
        );
        true
    }

    /// Copies the factor's block on the separator (its last rows and columns) into `l_ss`.
    fn gather_l_ss(&mut self) {
        let first = self.interior.len();
        let llt = supernodal(&self.symbolic, &self.l_values);
        for s in (0..llt.symbolic().n_supernodes()).rev() {
            let node = llt.supernode(s);
            let (start, val) = (node.start(), node.val());
            let ncols = val.ncols();
            if start + ncols <= first {
                break;
            }
            for c in start.max(first)..start + ncols {
                let j = c - start;
                for r in c..start + ncols {
                    self.l_ss[(r - first, c - first)] = val[(r - start, j)];
                }
                for (k, &r) in node.pattern().iter().enumerate() {
                    self.l_ss[(r - first, c - first)] = val[(ncols + k, j)];
                }
            }
        }
    }

    /// The forward pass: `Lᵢ z = [bᵢ; 0]` leaves `zᵢ = Lᵢᵢ⁻¹ bᵢ` and `zₛ = −Lₛₛ⁻¹ Lₛᵢ zᵢ`, so
    /// `cᵢ = Aₛᵢ Aᵢᵢ⁻¹ bᵢ = Lₛᵢ zᵢ = −Lₛₛ zₛ`.
    fn forward(&mut self, b: &[f64]) {
        let first = self.interior.len();
        for (z, &g) in self.rhs.iter_mut().zip(&self.interior) {
            *z = b[g];
        }
        self.rhs[first..].iter_mut().for_each(|z| *z = 0.0);
        let n = self.n();
        let z = MatMut::from_column_major_slice_mut(&mut self.rhs, n, 1);
        let stack = MemStack::new(&mut self.mem);
        supernodal(&self.symbolic, &self.l_values).l_solve_with_conj(Conj::No, z, Par::Seq, stack);
        let z_s = ColRef::from_slice(&self.rhs[first..]);
        let c = ColMut::from_slice_mut(&mut self.c);
        matmul(
            c.as_mat_mut(),
            BlockStructure::Rectangular,
            Accum::Replace,
            self.l_ss.as_ref(),
            BlockStructure::TriangularLower,
            z_s.as_mat(),
            BlockStructure::Rectangular,
            -1.0,
            Par::Seq,
        );
    }

    /// The backward pass: `Lᵢᵀ w = [zᵢ; Lₛₛᵀ xₛ]` gives `wₛ = xₛ` and `wᵢ = Aᵢᵢ⁻¹(bᵢ − Aᵢₛ xₛ) =
    /// xᵢ`, left in `rhs`.
    fn backward(&mut self, x_s: &[f64]) {
        let first = self.interior.len();
        let y = ColMut::from_slice_mut(&mut self.rhs[first..]);
        matmul(
            y.as_mat_mut(),
            BlockStructure::Rectangular,
            Accum::Replace,
            self.l_ss.as_ref().transpose(),
            BlockStructure::TriangularUpper,
            ColRef::from_slice(x_s).as_mat(),
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
        let n = self.n();
        let w = MatMut::from_column_major_slice_mut(&mut self.rhs, n, 1);
        let stack = MemStack::new(&mut self.mem);
        let llt = supernodal(&self.symbolic, &self.l_values);
        llt.l_transpose_solve_with_conj(Conj::No, w, Par::Seq, stack);
    }
}

impl SplitCholesky {
    /// The split of the matrix whose lower triangle has the pattern `col_ptr`, `row_idx`
    /// (compressed columns, rows sorted), cut along `key` if given (a coordinate per equation),
    /// or `None` when it has no fair split.
    pub fn new(col_ptr: &[usize], row_idx: &[usize], key: Option<&[f64]>) -> Option<SplitCholesky> {
        let n = col_ptr.len() - 1;
        if n < MIN_EQUATIONS {
            return None;
        }
        let key = key.filter(|k| k.len() == n);
        let [first, second, separator] = partition(&adjacency(n, col_ptr, row_idx), key)?;
        let ns = separator.len();
        let mut place = vec![usize::MAX; n];
        for (k, &g) in separator.iter().enumerate() {
            place[g] = k;
        }
        let mut separator_entries = Vec::new();
        for &c in &separator {
            for p in col_ptr[c]..col_ptr[c + 1] {
                let r = row_idx[p];
                if place[r] != usize::MAX {
                    let (a, b) = (place[r], place[c]);
                    separator_entries.push((a.max(b), a.min(b), p));
                }
            }
        }
        let req = cholesky_in_place_scratch::<f64>(ns, Par::Seq, Default::default());
        Some(SplitCholesky {
            halves: [
                Half::new(first, &separator, col_ptr, row_idx),
                Half::new(second, &separator, col_ptr, row_idx),
            ],
            separator,
            separator_entries,
            schur: Mat::zeros(ns, ns),
            dense_mem: MemBuffer::new(req),
        })
    }

    /// Factorizes the matrix stored in `values` (the caller's lower triangle); false when it is
    /// not positive definite.
    pub fn factor(&mut self, values: &[f64]) -> bool {
        let [h1, h2] = &mut self.halves;
        let (ok1, ok2) = rayon::join(|| h1.factor(values), || h2.factor(values));
        if !(ok1 && ok2) {
            return false;
        }
        let ns = self.separator.len();
        for c in 0..ns {
            for r in c..ns {
                self.schur[(r, c)] = h1.schur[(r, c)] + h2.schur[(r, c)];
            }
        }
        for &(r, c, p) in &self.separator_entries {
            self.schur[(r, c)] -= values[p];
        }
        cholesky_in_place(
            self.schur.as_mut(),
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut self.dense_mem),
            Default::default(),
        )
        .is_ok()
    }

    /// Solves with the last factorization, in place: `b` in, `x` out (the caller's numbering).
    pub fn solve_in_place(&mut self, x: &mut [f64]) {
        let [h1, h2] = &mut self.halves;
        let b = &*x;
        rayon::join(|| h1.forward(b), || h2.forward(b));
        let ns = self.separator.len();
        let mut x_s = Mat::<f64>::zeros(ns, 1);
        for (k, &g) in self.separator.iter().enumerate() {
            x_s[(k, 0)] = b[g] - h1.c[k] - h2.c[k];
        }
        solve_lower_triangular_in_place(self.schur.as_ref(), x_s.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(self.schur.as_ref().transpose(), x_s.as_mut(), Par::Seq);
        let x_s: Vec<f64> = (0..ns).map(|k| x_s[(k, 0)]).collect();
        rayon::join(|| h1.backward(&x_s), || h2.backward(&x_s));
        for h in [&*h1, &*h2] {
            for (z, &g) in h.rhs.iter().zip(&h.interior) {
                x[g] = *z;
            }
        }
        for (k, &g) in self.separator.iter().enumerate() {
            x[g] = x_s[k];
        }
    }
}

/// What the tests measure of a split: its separator and the entries it stores.
#[cfg(test)]
impl SplitCholesky {
    /// Equations on the separator.
    pub(super) fn separator_len(&self) -> usize {
        self.separator.len()
    }

    /// Entries stored for the factorization: the halves' sparse factors, and five dense
    /// blocks on the separator (each half's `Lᵢ,ₛₛ` and `Sᵢ`, and `S`).
    pub(super) fn factor_entries(&self) -> usize {
        let entries = |m: &Mat<f64>| m.nrows() * m.ncols();
        let halves: usize = (self.halves.iter())
            .map(|h| h.l_values.len() + entries(&h.schur) + entries(&h.l_ss))
            .sum();
        halves + entries(&self.schur)
    }
}
