//! Normal contact: a penalty on the signed distance `d` of a node to a tool (`n = ∇d` the
//! outward normal, `H = ∇n` the surface's curvature), eased in over a gap `δ` so that the
//! contact force and its stiffness grow continuously from zero as a node comes within `δ` of
//! the tool. With `y = δ − d` the depth into the gap:
//!
//! ```text
//!   p = k y²/(2δ),  φ'' = k y/δ,  φ = k y³/(6δ)          0 ≤ y ≤ δ     (p the pressing force, N)
//!   p = k (δ/2 − d),  φ'' = k,  φ = k (δ²/6 − δd/2 + d²/2)    d ≤ 0
//! ```
//!
//! The energy is C2, so Newton sees a contact before it closes instead of throwing a node that
//! hovers a micrometre off the tool deep into it, and no stiffness jumps where a light contact
//! sits (a jump there made the stiffest fabrics chatter between contact and none). The price:
//! where a node's contact force goes to zero at the solution (the edge of a contact patch) the
//! force has a double root, and Newton halves that node's depth each iteration instead of
//! squaring its error. For `d ≤ 0` the force is the plain penalty shifted by `kδ/2`: a node
//! carrying `F` sinks `F/k − δ/2`.
//!
//! The force on the node is `p n` (the residual gains `−p n`), its derivative
//! `φ'' n nᵀ − p H`: `φ'' n nᵀ` is positive semi-definite and joins the factorized tangent;
//! `−p H` (indefinite on a curved tool, and small: `p/k ≪` the tool's radius) is the rest.

/// What a penalty adds for one node and one tool.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Penalty {
    /// The pressing force `p`, N.
    pub force: f64,
    /// Added to the residual, N.
    pub residual: [f64; 3],
    /// `φ(d)`, N·mm.
    pub energy: f64,
    /// `φ'' n nᵀ`, N/mm.
    pub spd: [[f64; 3]; 3],
    /// `−p H`, N/mm.
    pub rest: [[f64; 3]; 3],
}

/// The pressing force `p(d)` (N), the stiffness `φ''(d)` (N/mm) and the energy `φ(d)` (N·mm)
/// for penalty `k` and smoothing gap `delta`; zero beyond the gap.
pub fn law(k: f64, delta: f64, d: f64) -> (f64, f64, f64) {
    if d >= delta {
        (0.0, 0.0, 0.0)
    } else if d >= 0.0 {
        let y = delta - d;
        (
            k * y * y / (2.0 * delta),
            k * y / delta,
            k * y * y * y / (6.0 * delta),
        )
    } else {
        (
            k * (0.5 * delta - d),
            k,
            k * (delta * delta / 6.0 - 0.5 * delta * d + 0.5 * d * d),
        )
    }
}

/// The penalty of a node at signed distance `d` with normal `n`, penalty `k` (N/mm), smoothing
/// gap `delta` (mm) and, when the tangent is wanted, the curvature `h`. `None` beyond the gap.
pub fn penalty(
    k: f64,
    delta: f64,
    d: f64,
    n: [f64; 3],
    h: Option<&[[f64; 3]; 3]>,
) -> Option<Penalty> {
    if d >= delta {
        return None;
    }
    let (p, stiffness, energy) = law(k, delta, d);
    let mut out = Penalty {
        force: p,
        residual: [-p * n[0], -p * n[1], -p * n[2]],
        energy,
        ..Default::default()
    };
    if let Some(h) = h {
        for a in 0..3 {
            for b in 0..3 {
                out.spd[a][b] = stiffness * n[a] * n[b];
                out.rest[a][b] = -p * h[a][b];
            }
        }
    }
    Some(out)
}
