//! Regularised Coulomb friction whose normal force and normal are those of the current state.
//!
//! A node in contact with a tool has a friction anchor `a` (where it stood at the step's start,
//! less the elastic slip it carried over, moving with the tool). A node that first touches the
//! tool within a step counts what it moved since the step's start as slip, and so carries
//! `μN` at once: an approximation of the order of the step. Its slip is the part of
//! `rel = x − a` in the tool's tangent plane, `s = P rel` with `P = I − n nᵀ`, and the friction
//! force on it is `−μ N s / ρ`, `ρ = sqrt(|s|² + ε²)`: full sliding carries `μ N`, and `ε` is the
//! slip that mobilises it. `N(x)`, `n(x)` are the normal force and normal at the node's current
//! position, so friction follows the state the step converges to (a backward-Euler step of
//! the slip), not the step's start.
//!
//! With `G = (I − s sᵀ/ρ²)/ρ` and `H = ∇n`, the derivative of the residual's `μ N s/ρ` is
//!
//! ```text
//!   μ N G P                                   symmetric, positive semi-definite
//! + μ (s/ρ) ⊗ ∇N − μ N G ((n·rel) H + n ⊗ Hᵀ rel)   the rest: not symmetric
//! ```
//!
//! For the line search, the potential `μ N̂ (sqrt(|P̂ rel|² + ε²) − ε)` with `N̂`, `n̂` frozen at
//! the Newton iterate has the residual's friction as its gradient there.

/// What friction adds for one node and one tool.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Friction {
    /// Added to the residual, N.
    pub residual: [f64; 3],
    /// `μ N (ρ − ε)` with this state's `N`, `n`, N·mm.
    pub energy: f64,
    /// `|μ N s/ρ|`, N.
    pub magnitude: f64,
    pub spd: [[f64; 3]; 3],
    pub rest: [[f64; 3]; 3],
}

/// The state friction is evaluated at.
#[derive(Clone, Copy, Debug)]
pub struct Contact {
    /// Coulomb coefficient.
    pub mu: f64,
    /// Regularisation slip ε, mm.
    pub eps: f64,
    /// Normal force `N` (N) and its gradient with respect to the node's position (N/mm).
    pub normal_force: f64,
    pub normal_force_gradient: [f64; 3],
    /// The tool's outward normal at the node.
    pub n: [f64; 3],
    /// `x − a`, mm.
    pub rel: [f64; 3],
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The tangential part of `rel` for the normal `n`.
pub fn tangential(n: [f64; 3], rel: [f64; 3]) -> [f64; 3] {
    let rn = dot(rel, n);
    [rel[0] - rn * n[0], rel[1] - rn * n[1], rel[2] - rn * n[2]]
}

/// The friction potential `μ N (sqrt(|P rel|² + ε²) − ε)` for given `N`, `n`.
pub fn potential(mu: f64, eps: f64, normal_force: f64, n: [f64; 3], rel: [f64; 3]) -> f64 {
    let s = tangential(n, rel);
    mu * normal_force * ((dot(s, s) + eps * eps).sqrt() - eps)
}

/// Friction at `c`; with `curvature` (the tool's `H` at the node) also its derivative.
pub fn friction(c: &Contact, curvature: Option<&[[f64; 3]; 3]>) -> Friction {
    let s = tangential(c.n, c.rel);
    let rho = (dot(s, s) + c.eps * c.eps).sqrt();
    if rho == 0.0 {
        // No slip and no regularisation: nothing to oppose yet.
        return Friction::default();
    }
    let mu_n = c.mu * c.normal_force;
    let mut out = Friction {
        residual: [mu_n * s[0] / rho, mu_n * s[1] / rho, mu_n * s[2] / rho],
        energy: mu_n * (rho - c.eps),
        magnitude: mu_n * dot(s, s).sqrt() / rho,
        ..Default::default()
    };
    let Some(h) = curvature else {
        return out;
    };
    let n = c.n;
    let rn = dot(c.rel, n);
    // Hᵀ rel (H = ∇n need not be symmetric: the unit normal of a field that is not a distance).
    let h_rel = [0, 1, 2].map(|b| (0..3).map(|j| h[j][b] * c.rel[j]).sum::<f64>());
    // G = (I − s sᵀ/ρ²)/ρ.
    let g = |a: usize, b: usize| ((a == b) as u8 as f64 - s[a] * s[b] / (rho * rho)) / rho;
    for a in 0..3 {
        for b in 0..3 {
            let p_ab = (a == b) as u8 as f64 - n[a] * n[b];
            out.spd[a][b] = mu_n * (p_ab - s[a] * s[b] / (rho * rho)) / rho;
            // ∂s/∂x − P = −(n·rel) H − n ⊗ (Hᵀ rel).
            let mut gq = 0.0;
            for k in 0..3 {
                gq += g(a, k) * (-rn * h[k][b] - n[k] * h_rel[b]);
            }
            out.rest[a][b] = c.mu * s[a] / rho * c.normal_force_gradient[b] + mu_n * gq;
        }
    }
    out
}
