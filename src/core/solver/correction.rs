//! The Newton correction: solve `(K + B + δD) Δu = −r`, where `K + spd(B) + δD` is the
//! symmetric tangent held by the sparse Cholesky factorization and `rest(B)` the nodal terms'
//! non-symmetric remainder (friction that follows the normal force, the tools' curvature).
//!
//! When the remainder is empty the factorization solves the system. Otherwise GMRES,
//! right-preconditioned by the factorization and started from its solution, takes the rest: the
//! preconditioned operator is the identity plus a perturbation of the size of μ, so a few
//! iterations reach the forcing tolerance. The correction is then Newton's (of the damped
//! tangent), unless the tangent had to be shifted to factorize (a mechanism: the shifted
//! factorization's correction is kept), GMRES reached its 30 iterations, or its correction would
//! not descend (the factorization's is kept).

use super::assembly::Workspace;
use super::model::Model;

/// How a correction was found.
#[derive(Clone, Debug)]
pub(super) struct Correction {
    /// The correction over the free dofs, mm.
    pub du: Vec<f64>,
    /// The diagonal shift the factorization needed (0: positive definite).
    pub shift: f64,
    /// GMRES iterations taken (0 when the factorization alone solved it).
    pub krylov_iterations: u32,
    /// `r · Δu`: negative for a descent direction of the merit.
    pub slope: f64,
}

/// The tangent could not be factorized even when shifted, or the solve gave a non-finite
/// correction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum CorrectionError {
    NotFactorizable,
    NonFinite,
}

/// Largest Krylov subspace before giving up on the forcing tolerance (the factorization's
/// correction is then kept, with whatever GMRES reached).
const MAX_KRYLOV: usize = 30;

/// Solves for the correction with relative forcing tolerance `forcing` on `‖J Δu + r‖/‖r‖`.
pub(super) fn solve(
    model: &mut Model,
    ws: &Workspace,
    r: &[f64],
    forcing: f64,
) -> Result<Correction, CorrectionError> {
    let info = model
        .linear
        .factor(&ws.values)
        .map_err(|_| CorrectionError::NotFactorizable)?;
    let mut du: Vec<f64> = r.iter().map(|v| -v).collect();
    model.linear.solve_in_place(&mut du);
    if !du.iter().all(|v| v.is_finite()) {
        return Err(CorrectionError::NonFinite);
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut krylov_iterations = 0;
    // The factorization's correction leaves `J du + r = rest · du` (its matrix solved the rest
    // exactly): GMRES only when that exceeds the forcing.
    let mut left = vec![0.0; du.len()];
    add_rest(model, ws, &du, &mut left);
    let norm_r = norm(r);
    if info.shift == 0.0 && norm(&left) > forcing * norm_r {
        let b: Vec<f64> = r.iter().map(|v| -v).collect();
        let mut x = du.clone();
        krylov_iterations = gmres(model, ws, &b, &mut x, forcing);
        // Keep the exact correction when it descends; otherwise the factorization's, which
        // always does (its matrix is positive definite).
        if x.iter().all(|v| v.is_finite()) && dot(r, &x) < 0.0 {
            du = x;
        }
    }
    let slope = dot(r, &du);
    Ok(Correction {
        du,
        shift: info.shift,
        krylov_iterations: krylov_iterations as u32,
        slope,
    })
}

/// `y = J x`: the stored symmetric tangent plus the remainder blocks.
fn apply_jacobian(model: &Model, ws: &Workspace, x: &[f64], y: &mut [f64], scratch: &mut Vec<f64>) {
    model.linear.mul(&ws.values, x, y, scratch);
    add_rest(model, ws, x, y);
}

/// `y += rest · x`: the remainder blocks, node by node, and the coupling.
fn add_rest(model: &Model, ws: &Workspace, x: &[f64], y: &mut [f64]) {
    if let Some(c) = ws.coupling.as_ref().filter(|c| c.total > 0.0) {
        let along: f64 = c.nodes.iter().map(|&(q, u)| u * x[q]).sum();
        for &(q, u) in &c.nodes {
            y[q] += u * (u * x[q] - along) / c.total;
        }
    }
    for (nd, block) in &ws.rest {
        for a in 0..3 {
            let row = model.eq[3 * nd + a];
            if row == usize::MAX {
                continue;
            }
            for c in 0..3 {
                let col = model.eq[3 * nd + c];
                if col != usize::MAX {
                    y[row] += block[a][c] * x[col];
                }
            }
        }
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// GMRES on `J x = b` from `x`, right-preconditioned by the factorization in `model.linear`,
/// until `‖b − J x‖ ≤ tol ‖b‖` or [`MAX_KRYLOV`] iterations. Returns the iterations taken.
fn gmres(model: &mut Model, ws: &Workspace, b: &[f64], x: &mut [f64], tol: f64) -> usize {
    let n = b.len();
    let mut scratch = Vec::new();
    let mut w = vec![0.0; n];
    apply_jacobian(model, ws, x, &mut w, &mut scratch);
    let r0: Vec<f64> = b.iter().zip(&w).map(|(b, a)| b - a).collect();
    let beta = norm(&r0);
    let target = tol * norm(b);
    if beta <= target || beta == 0.0 {
        return 0;
    }
    // Arnoldi basis V, preconditioned directions Z, Hessenberg H in Givens-rotated form.
    let mut v: Vec<Vec<f64>> = vec![r0.iter().map(|a| a / beta).collect()];
    let mut z: Vec<Vec<f64>> = Vec::new();
    let mut h: Vec<Vec<f64>> = Vec::new();
    let (mut cs, mut sn): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    let mut g = vec![beta];
    let mut k = 0;
    while k < MAX_KRYLOV {
        let mut zk = v[k].clone();
        model.linear.solve_in_place(&mut zk);
        apply_jacobian(model, ws, &zk, &mut w, &mut scratch);
        z.push(zk);
        let mut col = vec![0.0; k + 2];
        for (i, vi) in v.iter().enumerate() {
            let hij = w.iter().zip(vi).map(|(a, b)| a * b).sum::<f64>();
            col[i] = hij;
            for (wj, vj) in w.iter_mut().zip(vi) {
                *wj -= hij * vj;
            }
        }
        let hn = norm(&w);
        col[k + 1] = hn;
        for i in 0..k {
            let t = cs[i] * col[i] + sn[i] * col[i + 1];
            col[i + 1] = -sn[i] * col[i] + cs[i] * col[i + 1];
            col[i] = t;
        }
        let d = (col[k] * col[k] + col[k + 1] * col[k + 1]).sqrt();
        let (c, s) = if d > 0.0 {
            (col[k] / d, col[k + 1] / d)
        } else {
            (1.0, 0.0)
        };
        col[k] = d;
        col[k + 1] = 0.0;
        cs.push(c);
        sn.push(s);
        g.push(-s * g[k]);
        g[k] *= c;
        h.push(col);
        k += 1;
        if g[k].abs() <= target || hn <= 1e-14 * beta {
            break;
        }
        v.push(w.iter().map(|a| a / hn).collect());
    }
    // Back substitution for y, then x += Z y.
    let mut y = vec![0.0; k];
    for i in (0..k).rev() {
        let mut acc = g[i];
        for j in i + 1..k {
            acc -= h[j][i] * y[j];
        }
        y[i] = if h[i][i] != 0.0 { acc / h[i][i] } else { 0.0 };
    }
    for (zj, yj) in z.iter().zip(&y) {
        for (xi, zi) in x.iter_mut().zip(zj) {
            *xi += yj * zi;
        }
    }
    k
}
