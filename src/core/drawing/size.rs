//! How large a drawing is before anything is allocated: elements, dofs, the Cholesky factor's
//! entries and the memory they take, so a mesh too large for the machine can be refused first.

use super::DrawingProblem;

/// The size of a drawing's model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeEstimate {
    /// Elements of the solved part.
    pub elements: f64,
    /// Degrees of freedom of the solved part (before the symmetry planes take a few out).
    pub dofs: f64,
    /// Entries of the sparse Cholesky factor (measured on the yarn grids, AMD-ordered: about
    /// `12 n (log₂ n − 5.45)` for `n` dofs, within 15 % from 3,600 to 61,000 dofs), times
    /// 1.3 when it is factorized on two threads (the halves and the separator's dense blocks).
    pub factor_entries: f64,
    /// Peak memory of the solve, bytes.
    pub bytes: f64,
}

/// Bytes per element: its output (force, 12×12 tangent), geometry, crimp states and slots.
const BYTES_PER_ELEMENT: f64 = 2400.0;
/// Bytes per node: positions, displacements, contact pairs, blocks, residual buffers.
const BYTES_PER_NODE: f64 = 900.0;
/// Bytes per factor entry: the value and faer's supernodal bookkeeping.
const BYTES_PER_FACTOR_ENTRY: f64 = 12.0;
/// The fill of AMD on the yarn grid: `FILL n (log₂ n − FILL_OFFSET)` factor entries.
const FILL: f64 = 12.0;
const FILL_OFFSET: f64 = 5.45;
/// The factor entries of the two-thread factorization over the whole factor's: its halves
/// (each AMD-ordered on its own) and the separator's five dense blocks (measured 1.29–1.35
/// on the box from 3,600 to 40,000 dofs).
const SPLIT_FILL: f64 = 1.3;

impl DrawingProblem {
    /// The size of this drawing's model, computed from its numbers alone (floating point, so
    /// that absurd meshes do not overflow).
    pub fn size_estimate(&self) -> SizeEstimate {
        let quarter = self.quarter_applies();
        let share = if quarter { 0.5 } else { 1.0 };
        let per_axis = |b: f64| (share * b / self.element_size_mm).round().max(1.0);
        let (n1, n2) = (per_axis(self.blank_mm[0]), per_axis(self.blank_mm[1]));
        let elements = n1 * n2;
        let nodes = (n1 + 1.0) * (n2 + 1.0);
        let dofs = 3.0 * nodes;
        let mut factor_entries = FILL * dofs * (dofs.max(2.0).log2() - FILL_OFFSET).max(2.0);
        if self.solver.factorization_threads() > 1 {
            factor_entries *= SPLIT_FILL;
        }
        let bytes = BYTES_PER_ELEMENT * elements
            + BYTES_PER_NODE * nodes
            + BYTES_PER_FACTOR_ENTRY * factor_entries;
        SizeEstimate {
            elements,
            dofs,
            factor_entries,
            bytes,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_size_estimate_matches_the_model_it_describes() {
        // The estimate a too-large mesh is refused by, against the model actually built: element
        // and dof counts exactly, the Cholesky factor's entries to within 15 % (60 % on the
        // smallest mesh, where the estimate errs on the safe side).
        for (h, yarn_angle) in [
            (5.0, 90.0),
            (2.5, 90.0),
            (1.25, 90.0),
            (0.8, 90.0),
            (0.6, 90.0),
            (5.0, 80.0),
            (2.5, 80.0),
        ] {
            let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
            p.element_size_mm = h;
            p.yarn_angle_deg = yarn_angle;
            p.solver.factor_threads = 1;
            let estimate = p.size_estimate();
            let prepared = p.prepare().unwrap();
            let model = &prepared.model;
            let factor = model.sparsity().1 as f64;
            println!(
                "h {h} mm, yarns at {yarn_angle}°: {} elements, {} dofs, factor {factor:.3e} entries (estimate {:.3e})",
                model.mesh.quads.len(),
                model.mesh.dofs(),
                estimate.factor_entries
            );
            assert_eq!(estimate.elements, model.mesh.quads.len() as f64);
            assert_eq!(estimate.dofs, model.mesh.dofs() as f64);
            let tolerance = if model.mesh.dofs() < 3000 { 0.6 } else { 0.15 };
            assert!((estimate.factor_entries / factor - 1.0).abs() < tolerance);
        }
    }

    #[test]
    fn the_size_estimate_counts_the_two_thread_factorization() {
        use crate::core::solver::Solver;
        // On two threads the factorization is split in halves (`guide::solver`, "The factorization on one thread and on two") that store more
        // entries than the whole factor: the estimate counts them when two threads are asked for
        // (the estimate once undercounted them: 1.14 times the whole factor's entries in the halves
        // alone, and the separator's dense blocks besides).
        for (h, yarn_angle) in [(2.5, 90.0), (1.25, 90.0), (0.8, 90.0), (2.5, 80.0)] {
            let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
            p.element_size_mm = h;
            p.yarn_angle_deg = yarn_angle;
            p.solver.factor_threads = 2;
            let estimate = p.size_estimate();
            let mut prepared = p.prepare().unwrap();
            let whole = prepared.model.sparsity().1 as f64;
            let solver = Solver::new(&mut prepared.model, p.solver.clone());
            let split = solver.model.sparsity().1 as f64;
            println!(
                "h {h} mm, yarns at {yarn_angle}°: whole {whole:.3e}, split {split:.3e} ({:.3}×), estimate {:.3e}",
                split / whole,
                estimate.factor_entries
            );
            assert!(split > whole, "the halves store more than the whole");
            assert!((estimate.factor_entries / split - 1.0).abs() < 0.15);
            p.solver.factor_threads = 1;
            assert!(p.size_estimate().factor_entries < estimate.factor_entries);
        }
    }
}
