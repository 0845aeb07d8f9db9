//! Normal contact: a penalty on the signed distance `d` of a node to a tool (`n = ∇d` the
//! outward normal, `H = ∇n` the surface's curvature), eased in over a gap `δ` so that the
//! contact stiffness grows from `k_e = 0.2 k` at the gap's edge to `k` at the surface. With
//! `y = δ − d` the depth into the gap:
//!
//! ```text
//!   p(y) = k_e y + (k − k_e) y²/(2δ)                  0 ≤ y ≤ δ     the pressing force, N
//!   p(y) = p(δ) + k (y − δ)                           y ≥ δ (d ≤ 0)
//!   φ(y) = ∫ p dy                                     the energy, N·mm
//! ```
//!
//! Newton then sees a contact before it closes instead of throwing a node that hovers a
//! micrometre off the tool deep into it. For `d ≤ 0` the force is the plain penalty shifted by
//! `(k + k_e)δ/2`: a node carrying `F` sinks `F/k − (1 + k_e/k)δ/2`.
//!
//! The force on the node is `p n` (the residual gains `−p n`), its derivative
//! `φ'' n nᵀ − p H`: `φ'' n nᵀ` is positive semi-definite and joins the factorized tangent;
//! `−p H` (indefinite on a curved tool, and small: `p/k ≪` the tool's radius) is the rest.

/// What a penalty adds for one node and one tool.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Penalty {
    /// The pressing force `p`, N.
    pub force: f64,
    /// `φ''(d)`, N/mm.
    pub stiffness: f64,
    /// Added to the residual, N.
    pub residual: [f64; 3],
    /// `φ(d)`, N·mm.
    pub energy: f64,
    /// `φ'' n nᵀ`, N/mm.
    pub spd: [[f64; 3]; 3],
    /// `−p H`, N/mm.
    pub rest: [[f64; 3]; 3],
}

/// The share of the penalty's stiffness at the gap's edge, `k_e/k`: the force grows from zero
/// with a slope (a simple root, so Newton converges quadratically onto a node leaving a tool;
/// with zero slope it would only halve the gap each iteration).
pub const EDGE_STIFFNESS: f64 = 0.2;

/// The pressing force `p(d)` (N), the stiffness `φ''(d)` (N/mm) and the energy `φ(d)` (N·mm)
/// for penalty `k` and smoothing gap `delta`; zero beyond the gap.
pub fn law(k: f64, delta: f64, d: f64) -> (f64, f64, f64) {
    let y = delta - d;
    if y <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let ke = EDGE_STIFFNESS * k;
    if y <= delta {
        (
            ke * y + (k - ke) * y * y / (2.0 * delta),
            ke + (k - ke) * y / delta,
            ke * y * y / 2.0 + (k - ke) * y * y * y / (6.0 * delta),
        )
    } else {
        let p_edge = 0.5 * (k + ke) * delta;
        let phi_edge = ke * delta * delta / 2.0 + (k - ke) * delta * delta / 6.0;
        let z = y - delta;
        (p_edge + k * z, k, phi_edge + p_edge * z + 0.5 * k * z * z)
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
        stiffness,
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
