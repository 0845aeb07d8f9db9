//! A Newton correction with each node's contact put back where its own balance lies.
//!
//! Newton's correction balances a linear model of every term. The contact's eased gap is not
//! linear: where a contact fades out (a node lifting off a tool, its force `k y²/2δ` going to
//! zero) the linear model halves the node's depth at each correction instead of squaring its
//! error, and a node coming onto a tool it did not touch is thrown through the gap. A node's
//! share of the correction along the tool's normal is one unknown with one equation, its own
//! normal balance, in which all the rest of the correction is held: solved exactly for the
//! penalty (the rest linear, with the node's own stiffness from the tangent), it takes the
//! node to its balance in one correction. This is the nonlinear elimination of those dofs
//! (Cai and Li's inexact Newton with nonlinear elimination): the tangent, the factorization
//! and the other dofs' corrections are unchanged, and the line search judges the result.

use super::Solver;
use super::correction::Correction;
use super::terms::{NodalTerms, OwnStiffness};

impl Solver<'_> {
    /// Correction `c`, solved at residual `r` and load `lambda`, reshaped by the nodal terms'
    /// [`NodalTerms::reshape`] with each node's stiffness from the tangent just factorized,
    /// its slope `r · Δu` taken again; as solved when the reshaped one would not descend (or
    /// `SolverOptions::reshape_contact` is off).
    pub(super) fn reshape(
        &self,
        lambda: f64,
        terms: &dyn NodalTerms,
        r: &[f64],
        mut c: Correction,
    ) -> Correction {
        if !self.options.reshape_contact {
            return c;
        }
        let model = &*self.model;
        let eq = &model.eq;
        let x = model.positions();
        let mut du = vec![[0.0; 3]; x.len()];
        for (d, &q) in eq.iter().enumerate() {
            if q != usize::MAX {
                du[d / 3][d % 3] = c.du[q];
            }
        }
        let values = &self.ws.values;
        let stiffness = |i: usize| -> Option<OwnStiffness> {
            let slots = &model.node_slots[i];
            let free = [0, 1, 2].map(|a| slots[4 * a] != u32::MAX);
            let mut k = [[0.0; 3]; 3];
            for a in 0..3 {
                for b in 0..3 {
                    let s = slots[3 * a + b];
                    if s != u32::MAX {
                        k[a][b] = values[s as usize];
                    }
                }
            }
            free.contains(&true).then_some(OwnStiffness { k, free })
        };
        if !terms.reshape(lambda, &x, &mut du, &stiffness) {
            return c;
        }
        let mut reshaped = vec![0.0; c.du.len()];
        for (d, &q) in eq.iter().enumerate() {
            if q != usize::MAX {
                reshaped[q] = du[d / 3][d % 3];
            }
        }
        let slope: f64 = r.iter().zip(&reshaped).map(|(a, b)| a * b).sum();
        if slope < 0.0 {
            c.du = reshaped;
            c.slope = slope;
        }
        c
    }
}
