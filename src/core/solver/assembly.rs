//! Assembly of one configuration: the fabric's elements and the nodal terms into the residual
//! over the free dofs, the potential, the load scale and (when asked) the tangent: its
//! symmetric part into the sparse matrix that is factorized, the nodal terms' non-symmetric
//! rest into a list of 3×3 node blocks.

use super::model::{Model, hinge_pair, pair_index};
use super::terms::{NodalTerms, NodeBlock, RankOne};

/// What the assembly of one configuration produced (the tangent stays in the [`Workspace`]).
#[derive(Clone, Debug)]
pub(super) struct Assembly {
    /// Residual `f_int − f_ext` over the free dofs, N.
    pub r: Vec<f64>,
    /// The potential at this configuration, N·mm: stored energy plus the nodal terms'
    /// potential with their non-conservative parts taken here (the merit when it is a base).
    pub energy: f64,
    /// The same with those parts frozen at the last base (the merit of a trial).
    pub energy_frozen: f64,
    /// Load scale: the larger of the internal force norm and the nodal terms' scale, N.
    pub scale: f64,
    /// The configuration is admissible and every residual entry is finite.
    pub admissible: bool,
}

/// A coupling on nodes as one on the free dofs (their z dofs; prescribed ones dropped).
fn free_coupling(model: &Model, c: RankOne) -> RankOne {
    RankOne {
        nodes: (c.nodes.into_iter())
            .filter_map(|(nd, u)| {
                let q = model.eq[3 * nd + 2];
                (q != usize::MAX).then_some((q, u))
            })
            .collect(),
        total: c.total,
    }
}

/// Buffers reused by every assembly.
pub(super) struct Workspace {
    /// The stored triangle of the symmetric tangent (elements + the nodal terms' `spd`).
    pub values: Vec<f64>,
    /// The nodal terms' blocks of the last tangent assembly, per node.
    pub blocks: Vec<NodeBlock>,
    /// The nodes whose `rest` block is not zero, with that block (its rows and columns of
    /// prescribed dofs are skipped where it is applied).
    pub rest: Vec<(usize, [[f64; 3]; 3])>,
    /// The nodal terms' coupling of the last tangent assembly, over the free dofs.
    pub coupling: Option<RankOne>,
    pub x: Vec<[f64; 3]>,
    f_all: Vec<f64>,
    /// Law iterations summed over the assemblies (for the statistics).
    pub law_iterations: u64,
    pub parallel: bool,
}

impl Workspace {
    pub fn new(model: &Model, parallel: bool) -> Workspace {
        Workspace {
            values: vec![0.0; model.linear.nnz()],
            blocks: vec![NodeBlock::default(); model.mesh.nodes.len()],
            rest: Vec::new(),
            coupling: None,
            x: model.positions(),
            f_all: vec![0.0; model.u.len()],
            law_iterations: 0,
            parallel,
        }
    }

    /// Residual (and tangent if `tangent`) at the model's current displacements.
    pub fn assemble(
        &mut self,
        model: &mut Model,
        lambda: f64,
        terms: &dyn NodalTerms,
        tangent: bool,
    ) -> Assembly {
        model.positions_into(&mut self.x);
        self.law_iterations += model.evaluate_elements_at(&self.x, tangent, self.parallel);
        self.f_all.iter_mut().for_each(|v| *v = 0.0);
        model.add_internal_force(&mut self.f_all);
        let internal_norm = self.f_all.iter().map(|v| v * v).sum::<f64>().sqrt();
        if tangent {
            self.add_element_tangents(model);
            self.add_hinge_tangents(model);
        }
        let added = if tangent {
            self.blocks
                .iter_mut()
                .for_each(|b| *b = NodeBlock::default());
            let added = terms.add(lambda, &self.x, &mut self.f_all, Some(&mut self.blocks));
            self.add_node_blocks(model);
            self.coupling = terms.coupling(&self.x).map(|c| free_coupling(model, c));
            added
        } else {
            terms.add(lambda, &self.x, &mut self.f_all, None)
        };
        let sums = added.unwrap_or_default();
        let mut r = vec![0.0; model.free_dofs()];
        for (d, &q) in model.eq.iter().enumerate() {
            if q != usize::MAX {
                r[q] = self.f_all[d];
            }
        }
        let stored = model.stored_energy();
        let finite = r.iter().all(|v| v.is_finite());
        Assembly {
            r,
            energy: stored + sums.energy,
            energy_frozen: stored + sums.energy_frozen,
            scale: internal_norm.max(sums.scale),
            admissible: added.is_some() && finite,
        }
    }

    fn add_element_tangents(&mut self, model: &Model) {
        self.values.iter_mut().for_each(|v| *v = 0.0);
        for ((out, slots), &twice) in model
            .outputs
            .iter()
            .zip(&model.element_slots)
            .zip(&model.element_twice)
        {
            for i in 0..12 {
                for j in i..12 {
                    let s = slots[pair_index(i, j)];
                    if s != u32::MAX {
                        self.values[s as usize] += out.k[i][j];
                    }
                }
            }
            if twice == 0 {
                continue;
            }
            // A collapsed quad: the mirror (j, i) of a pair on one global dof, once more.
            for i in 0..12 {
                for j in i + 1..12 {
                    let p = pair_index(i, j);
                    if (twice >> p) & 1 == 1 && slots[p] != u32::MAX {
                        self.values[slots[p] as usize] += out.k[j][i];
                    }
                }
            }
        }
    }

    /// The bending hinges' tangents into the stored triangle, each upper pair once (a hinge's
    /// three nodes are distinct, so no two of its pairs share a stored entry).
    fn add_hinge_tangents(&mut self, model: &Model) {
        for (out, slots) in model.hinge_outputs.iter().zip(&model.hinge_slots) {
            for i in 0..9 {
                for j in i..9 {
                    let s = slots[hinge_pair(i, j)];
                    if s != u32::MAX {
                        self.values[s as usize] += out.k[i][j];
                    }
                }
            }
        }
    }

    /// The `spd` parts into the stored triangle (each symmetric pair once), the `rest` parts
    /// into the list the Krylov operator applies.
    fn add_node_blocks(&mut self, model: &Model) {
        self.rest.clear();
        for (nd, b) in self.blocks.iter().enumerate() {
            let slots = &model.node_slots[nd];
            for a in 0..3 {
                for c in a..3 {
                    let s = slots[3 * a + c];
                    if s != u32::MAX && b.spd[a][c] != 0.0 {
                        self.values[s as usize] += b.spd[a][c];
                    }
                }
            }
            if b.rest.iter().flatten().any(|v| *v != 0.0) {
                self.rest.push((nd, b.rest));
            }
        }
    }

    /// Adds `damping · cell stiffness` to the diagonal of every free dof (the pseudo-transient
    /// term of the Newton corrections; it never enters the residual).
    pub fn add_damping(&mut self, model: &Model, damping: f64) {
        if damping <= 0.0 {
            return;
        }
        for (nd, k) in model.cell_stiffness.iter().enumerate() {
            for a in 0..3 {
                let s = model.node_slots[nd][4 * a];
                if s != u32::MAX {
                    self.values[s as usize] += damping * k;
                }
            }
        }
    }
}
