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
//! force has a double root, and Newton's linear model halves that node's depth each iteration
//! instead of squaring its error; [`balancing_move`] solves the node's own balance in each
//! correction instead (`crate::core::solver::SolverOptions::reshape_contact`). For `d ≤ 0` the
//! force is the plain penalty shifted by `kδ/2`: a node carrying `F` sinks `F/k − δ/2`.
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

/// The outward move `s` (mm) that balances a node's penalty against the rest of its normal
/// load when that rest is linear in the move: the root of `p(y0 − s) = g + K s`, with `y0 =
/// δ − d` the node's depth into the gap before the move, `g` (N) the load pressing it into the
/// tool and `K ≥ 0` (N/mm) its stiffness against moving out (fabric, holder, damping), for
/// penalty `k` and gap `delta`. `p` rises with the depth, so the root is unique; `None` when
/// there is none (`K = 0` and the load pulls the node off the tool: the move is not bounded).
///
/// Newton linearises `p` where the node is, and where a contact fades out (`p = k y²/2δ`) its
/// linear model halves the depth at each correction. Put back into a node's share of the
/// correction, this root is where the node's own balance lies, reached in one correction.
pub fn balancing_move(k: f64, delta: f64, y0: f64, g: f64, stiffness: f64) -> Option<f64> {
    if !(stiffness >= 0.0 && k > 0.0 && delta > 0.0 && g.is_finite() && y0.is_finite()) {
        return None;
    }
    // In the depth y = y0 − s: p(y) + K y = R, the left side rising in y.
    let rhs = g + stiffness * y0;
    let y = if rhs <= 0.0 {
        // Off the tool (p = 0): K y = R.
        if stiffness == 0.0 {
            return None;
        }
        rhs / stiffness
    } else if 0.5 * k * delta + stiffness * delta >= rhs {
        // In the gap: k y²/2δ + K y = R (the stable root).
        2.0 * rhs / (stiffness + (stiffness * stiffness + 2.0 * k * rhs / delta).sqrt())
    } else {
        // Pressed: k (y − δ/2) + K y = R.
        (rhs + 0.5 * k * delta) / (k + stiffness)
    };
    Some(y0 - y)
}
