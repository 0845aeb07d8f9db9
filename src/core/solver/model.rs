//! The finite-element model of a woven blank: its elements made of woven cells, the dof
//! numbering with the prescribed dofs taken out, the tangent's sparsity pattern (built and
//! ordered once) and the current state (displacements, crimp of every cell).

use rayon::prelude::*;

use crate::core::fabric::bending::{self, Hinge, HingeResponse};
use crate::core::fabric::law::{CellLaw, CrimpState};
use crate::core::membrane::element::{self, ElementGeometry, ElementOutput, GAUSS, GeometryError};
use crate::core::membrane::mesh::Mesh;
use crate::core::sparse::linear::{SparseCholesky, UpperPattern};

/// An element of the initial mesh cannot be built.
#[derive(Clone, Debug, PartialEq)]
pub struct BadElement {
    pub element: usize,
    pub cause: GeometryError,
}

impl std::fmt::Display for BadElement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let why = match self.cause {
            GeometryError::Degenerate => "it is degenerate or inverted",
            GeometryError::YarnOutOfPlane => "a yarn direction is normal to it",
        };
        write!(
            f,
            "element {} of the initial mesh is unusable: {why}",
            self.element
        )
    }
}

/// The model and its current state.
pub struct Model {
    pub mesh: Mesh,
    pub law: CellLaw,
    pub geometry: Vec<ElementGeometry>,
    /// Displacements, `[3·node + m]`, mm.
    pub u: Vec<f64>,
    /// Crimp state of each Gauss point's cells.
    pub crimp: Vec<[CrimpState; GAUSS]>,
    /// Equation number of each dof (`usize::MAX` when prescribed).
    pub(super) eq: Vec<usize>,
    /// Slots of each element's upper-triangle pairs (`i ≤ j` over 12 dofs), `u32::MAX` if none.
    pub(super) element_slots: Vec<[u32; 78]>,
    /// For each element, the pairs `i < j` (bit `pair_index(i, j)`) whose two dofs are the
    /// same global dof (a quad collapsed into a triangle): their entry counts twice in the
    /// stored triangle, once for `(i, j)` and once for its mirror `(j, i)`.
    pub(super) element_twice: Vec<u128>,
    /// Slots of each node's 3×3 block, row-major, `u32::MAX` where a dof is prescribed. Both
    /// halves of the block name the same stored entry.
    pub(super) node_slots: Vec<[u32; 9]>,
    pub(super) linear: SparseCholesky,
    /// The cells' tensile stiffness carried by each node, `C̄/L̄0 · cells`, N/mm: the scale of the
    /// damping of the Newton corrections.
    pub(super) cell_stiffness: Vec<f64>,
    pub(super) outputs: Vec<ElementOutput>,
    /// The bending hinges along the yarn lines ([`crate::core::fabric::bending`]; none: the paper's
    /// membrane), the slots of their 9×9 upper triangles and their last evaluation.
    pub hinges: Vec<Hinge>,
    pub(super) hinge_slots: Vec<[u32; 45]>,
    pub(super) hinge_outputs: Vec<HingeResponse>,
    /// Reference length for displacement tolerances: the mean element size, mm.
    pub element_size: f64,
}

/// Index of the pair `(i, j)`, `i ≤ j < 12`, in the 78 upper-triangle pairs.
pub(super) fn pair_index(i: usize, j: usize) -> usize {
    i * 12 - i * (i + 1) / 2 + j
}

/// The equation number of every dof, prescribed ones `usize::MAX`, and how many there are.
fn number_equations(ndof: usize, prescribed_dofs: &[usize]) -> (Vec<usize>, usize) {
    let mut eq = vec![0usize; ndof];
    for &d in prescribed_dofs {
        eq[d] = usize::MAX;
    }
    let mut n = 0;
    for e in eq.iter_mut() {
        if *e != usize::MAX {
            *e = n;
            n += 1;
        }
    }
    (eq, n)
}

/// Index of the pair `(i, j)`, `i ≤ j < 9`, in a hinge's 45 upper-triangle pairs.
pub(super) fn hinge_pair(i: usize, j: usize) -> usize {
    i * 9 - i * (i + 1) / 2 + j
}

/// The global dof of hinge-local dof `i` (`3·k + m`) of a hinge on `nodes`.
fn hinge_dof(nodes: &[usize; 3], i: usize) -> usize {
    3 * nodes[i / 3] + i % 3
}

/// Each hinge's upper-triangle pairs over free dofs: `(hinge, pair, row, col)`, `row ≤ col`.
fn hinge_pairs<'a>(
    hinges: &'a [Hinge],
    eq: &'a [usize],
) -> impl Iterator<Item = (usize, usize, usize, usize)> + 'a {
    hinges.iter().enumerate().flat_map(move |(k, h)| {
        (0..9).flat_map(move |i| {
            (i..9).filter_map(move |j| {
                let (a, b) = (eq[hinge_dof(&h.nodes, i)], eq[hinge_dof(&h.nodes, j)]);
                (a != usize::MAX && b != usize::MAX).then_some((
                    k,
                    hinge_pair(i, j),
                    a.min(b),
                    a.max(b),
                ))
            })
        })
    })
}

/// Where in the stored tangent each hinge's upper-triangle pairs go (`u32::MAX` where a dof is
/// prescribed).
fn hinge_slots(hinges: &[Hinge], eq: &[usize], linear: &SparseCholesky) -> Vec<[u32; 45]> {
    let mut slots = vec![[u32::MAX; 45]; hinges.len()];
    for (k, pair, a, b) in hinge_pairs(hinges, eq) {
        slots[k][pair] = linear.slot(a, b).expect("pair in pattern") as u32;
    }
    slots
}

/// The global dof of element-local dof `i` (`3·k + m`) of quad `q`.
fn element_dof(q: &[usize; 4], i: usize) -> usize {
    3 * q[i / 3] + i % 3
}

/// Where in the stored tangent each element's upper-triangle pairs and each node's 3×3 block
/// go (`u32::MAX` where a dof is prescribed).
fn slots(mesh: &Mesh, eq: &[usize], linear: &SparseCholesky) -> (Vec<[u32; 78]>, Vec<[u32; 9]>) {
    let slot = |a: usize, b: usize| -> u32 {
        if a == usize::MAX || b == usize::MAX {
            u32::MAX
        } else {
            linear.slot(a, b).expect("pair in pattern") as u32
        }
    };
    let element_slots = mesh
        .quads
        .iter()
        .map(|q| {
            let mut s = [u32::MAX; 78];
            for i in 0..12 {
                for j in i..12 {
                    s[pair_index(i, j)] = slot(eq[element_dof(q, i)], eq[element_dof(q, j)]);
                }
            }
            s
        })
        .collect();
    let node_slots = (0..mesh.nodes.len())
        .map(|nd| {
            let mut s = [u32::MAX; 9];
            for a in 0..3 {
                for b in 0..3 {
                    s[3 * a + b] = slot(eq[3 * nd + a], eq[3 * nd + b]);
                }
            }
            s
        })
        .collect();
    (element_slots, node_slots)
}

/// The cells' tensile stiffness each node carries, `C̄/L̄0 · cells`, N/mm.
fn cell_stiffness(mesh: &Mesh, geometry: &[ElementGeometry], law: &CellLaw) -> Vec<f64> {
    let c_mean = 0.5 * (law.p.c[0] + law.p.c[1]);
    let l_mean = 0.5 * (law.p.l0[0] + law.p.l0[1]);
    let mut stiffness = vec![0.0; mesh.nodes.len()];
    for (q, g) in mesh.quads.iter().zip(geometry) {
        for &nd in q {
            stiffness[nd] += 0.25 * g.cell_count() * c_mean / l_mean;
        }
    }
    stiffness
}

impl Model {
    /// Builds the model: element geometry, the dof numbering with `prescribed_dofs` removed, the
    /// sparsity pattern and its symbolic factorization.
    pub fn new(mesh: Mesh, law: CellLaw, prescribed_dofs: &[usize]) -> Result<Model, BadElement> {
        Model::with_hinges(mesh, law, prescribed_dofs, Vec::new())
    }

    /// [`Model::new`] with bending hinges along the yarn lines.
    pub fn with_hinges(
        mesh: Mesh,
        law: CellLaw,
        prescribed_dofs: &[usize],
        hinges: Vec<Hinge>,
    ) -> Result<Model, BadElement> {
        let cell_lengths = law.p.l0[0] * law.p.l0[1];
        let geometry = mesh
            .quads
            .iter()
            .enumerate()
            .map(|(e, q)| {
                let x0 = q.map(|n| mesh.nodes[n]);
                ElementGeometry::new(&x0, mesh.yarns, cell_lengths)
                    .map_err(|cause| BadElement { element: e, cause })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let (eq, n) = number_equations(mesh.dofs(), prescribed_dofs);
        let couplings = mesh.quads.iter().flat_map(|q| {
            let eq = &eq;
            (0..12).flat_map(move |i| {
                (i..12).filter_map(move |j| {
                    let (a, b) = (eq[element_dof(q, i)], eq[element_dof(q, j)]);
                    (a != usize::MAX && b != usize::MAX).then_some((a, b))
                })
            })
        });
        let linear = SparseCholesky::new(UpperPattern::from_couplings(
            n,
            couplings.chain(hinge_pairs(&hinges, &eq).map(|(_, _, a, b)| (a, b))),
        ));
        let (element_slots, node_slots) = slots(&mesh, &eq, &linear);
        let hinge_slots = hinge_slots(&hinges, &eq, &linear);
        let element_twice = mesh
            .quads
            .iter()
            .map(|q| {
                let mut bits = 0u128;
                for i in 0..12 {
                    for j in i + 1..12 {
                        if element_dof(q, i) == element_dof(q, j) {
                            bits |= 1 << pair_index(i, j);
                        }
                    }
                }
                bits
            })
            .collect();
        let cell_stiffness = cell_stiffness(&mesh, &geometry, &law);
        let element_size =
            (geometry.iter().map(|g| g.area0).sum::<f64>() / geometry.len().max(1) as f64).sqrt();
        let ne = mesh.quads.len();
        Ok(Model {
            u: vec![0.0; mesh.dofs()],
            crimp: vec![[law.initial_state(); GAUSS]; ne],
            eq,
            element_slots,
            element_twice,
            node_slots,
            linear,
            cell_stiffness,
            outputs: vec![ElementOutput::default(); ne],
            hinge_outputs: vec![HingeResponse::default(); hinges.len()],
            hinge_slots,
            hinges,
            element_size,
            geometry,
            mesh,
            law,
        })
    }

    /// Free (solved-for) dofs.
    pub fn free_dofs(&self) -> usize {
        self.linear.n()
    }

    /// Current nodal positions, mm.
    pub fn positions(&self) -> Vec<[f64; 3]> {
        let mut x = vec![[0.0; 3]; self.mesh.nodes.len()];
        self.positions_into(&mut x);
        x
    }

    pub(super) fn positions_into(&self, x: &mut [[f64; 3]]) {
        for (i, (xi, x0)) in x.iter_mut().zip(&self.mesh.nodes).enumerate() {
            for m in 0..3 {
                xi[m] = x0[m] + self.u[3 * i + m];
            }
        }
    }

    /// Sets the displacements from nodal positions on the free dofs only.
    pub(super) fn set_free_positions(&mut self, x: &[[f64; 3]]) {
        for (d, &q) in self.eq.iter().enumerate() {
            if q != usize::MAX {
                self.u[d] = x[d / 3][d % 3] - self.mesh.nodes[d / 3][d % 3];
            }
        }
    }

    fn element_positions(&self, e: usize, x: &[[f64; 3]]) -> [[f64; 3]; 4] {
        self.mesh.quads[e].map(|n| x[n])
    }

    /// Element outputs (forces, tensions) of the last evaluation.
    pub fn element_outputs(&self) -> &[ElementOutput] {
        &self.outputs
    }

    /// Evaluates every element at the current displacements (tensions, forces, optionally
    /// tangents), in parallel when `parallel`. Returns the law's Newton iterations.
    pub fn evaluate_elements(&mut self, tangent: bool, parallel: bool) -> u64 {
        let x = self.positions();
        self.evaluate_elements_at(&x, tangent, parallel)
    }

    /// Where each free dof's node lies along the blank's longer extent (its reference x or y,
    /// mm): the median of it cuts the blank in two for the two-thread factorization.
    pub(super) fn cut_key(&self) -> Vec<f64> {
        let extent = |a: usize| {
            let v = self.mesh.nodes.iter().map(|p| p[a]);
            v.clone().fold(f64::NEG_INFINITY, f64::max) - v.fold(f64::INFINITY, f64::min)
        };
        let axis = if extent(0) >= extent(1) { 0 } else { 1 };
        let mut key = vec![0.0; self.free_dofs()];
        for (d, &q) in self.eq.iter().enumerate() {
            if q != usize::MAX {
                key[q] = self.mesh.nodes[d / 3][axis];
            }
        }
        key
    }

    /// [`Model::evaluate_elements`] at given nodal positions (those of the current
    /// displacements), so a caller that needs them too computes them once.
    pub(super) fn evaluate_elements_at(
        &mut self,
        x: &[[f64; 3]],
        tangent: bool,
        parallel: bool,
    ) -> u64 {
        for (h, out) in self.hinges.iter().zip(&mut self.hinge_outputs) {
            *out = bending::evaluate(h.k, h.nodes.map(|n| x[n]), tangent);
        }
        let quads = &self.mesh.quads;
        let geometry = &self.geometry;
        let law = &self.law;
        let work = |(e, (out, crimp)): (usize, (&mut ElementOutput, &mut [CrimpState; GAUSS]))| {
            let xe = quads[e].map(|n| x[n]);
            element::evaluate(&geometry[e], law, &xe, crimp, tangent, out);
            out.law_iterations as u64
        };
        if parallel {
            self.outputs
                .par_iter_mut()
                .zip(self.crimp.par_iter_mut())
                .enumerate()
                .with_min_len(64)
                .map(work)
                .sum()
        } else {
            self.outputs
                .iter_mut()
                .zip(self.crimp.iter_mut())
                .enumerate()
                .map(work)
                .sum()
        }
    }

    /// The internal force vector of all dofs (reactions at prescribed dofs), from the last
    /// element evaluation.
    pub fn internal_force(&self) -> Vec<f64> {
        let mut f = vec![0.0; self.u.len()];
        self.add_internal_force(&mut f);
        f
    }

    pub(super) fn add_internal_force(&self, f: &mut [f64]) {
        for (q, out) in self.mesh.quads.iter().zip(&self.outputs) {
            for i in 0..12 {
                f[3 * q[i / 3] + i % 3] += out.f[i];
            }
        }
        for (h, out) in self.hinges.iter().zip(&self.hinge_outputs) {
            for i in 0..9 {
                f[hinge_dof(&h.nodes, i)] += out.f[i];
            }
        }
    }

    /// Stored energy of the fabric at the last evaluation, N·mm.
    pub fn stored_energy(&self) -> f64 {
        let hinges: f64 = self.hinge_outputs.iter().map(|o| o.energy).sum();
        self.outputs.iter().map(|o| o.energy).sum::<f64>() + hinges
    }

    /// Shear angle of each element, degrees.
    pub fn shear_angles_deg(&self) -> Vec<f64> {
        let x = self.positions();
        (0..self.mesh.quads.len())
            .map(|e| element::shear_angle_deg(&self.geometry[e], &self.element_positions(e, &x)))
            .collect()
    }

    /// Each element's least principal membrane force at the last evaluation, N/mm (positive:
    /// taut in every direction of its plane; [`element::least_membrane_force_n_per_mm`]).
    pub fn least_membrane_force_n_per_mm(&self) -> Vec<f64> {
        let x = self.positions();
        (0..self.mesh.quads.len())
            .map(|e| {
                let xe = self.element_positions(e, &x);
                let t = &self.outputs[e].tension;
                element::least_membrane_force_n_per_mm(&self.geometry[e], &self.law, &xe, t)
            })
            .collect()
    }

    /// Largest yarn tension of each element (over its Gauss points and yarns), N.
    pub fn max_tension_n(&self) -> Vec<f64> {
        self.outputs
            .iter()
            .map(|o| o.tension.iter().flatten().fold(0.0f64, |a, &b| a.max(b)))
            .collect()
    }
}

/// What the tests measure of a model's tangent.
#[cfg(test)]
impl Model {
    /// Non-zeros of the tangent's stored triangle and of its Cholesky factor.
    pub(crate) fn sparsity(&self) -> (usize, usize) {
        (self.linear.nnz(), self.linear.factor_nnz())
    }
}
