//! Every closed form and reference value the tests compare the code against, in one place.
//! None of it calls the crate's numerics: each answer comes from a formula (the paper's, a
//! textbook's, or geometry) or from a value worked out outside the code (the reference values
//! given in `src/guide/theory.md` and the closed forms of `src/guide/verification.md`).
//!
//! Units as in the code: mm, N, MPa (= N/mm²), radians unless a name says degrees.
#![allow(dead_code)]

use wovenform::core::fabric::law::CellParams;

// ---------------------------------------------------------------------------------------
// Friction and the blank holder
// ---------------------------------------------------------------------------------------

/// The capstan (Euler–Eytelwein) belt-friction ratio `T_out / T_in = exp(μ θ)`: a string
/// sliding over a rigid cylinder with Coulomb friction `mu` (dimensionless) over a wrap angle
/// `theta` (rad). Independent of the cylinder's radius. For μ = 0.2, θ = π/2: 1.3691
/// (`src/guide/verification.md`, "Capstan").
pub fn capstan_ratio(mu: f64, theta: f64) -> f64 {
    (mu * theta).exp()
}

/// The force (N) that pulls a strip of area `area` (mm²) out from under the blank holder at
/// pressure `pressure` (MPa) with Coulomb friction `mu`: `2 μ p S`, friction on both faces,
/// the die's and the holder's (`src/guide/verification.md`, "Holder pull-out").
pub fn holder_pull_out_force(mu: f64, pressure: f64, area: f64) -> f64 {
    2.0 * mu * pressure * area
}

/// Regularised Coulomb friction: the share of the full `μ N` that a slip `slip` (mm) in the
/// tool's tangent plane mobilises, `|s| / sqrt(|s|² + ε²)` with the regularisation length
/// `eps` (mm). Tends to 1 (sliding) for `|s| ≫ ε` and is linear in `s` (sticking, an elastic
/// spring) for `|s| ≪ ε`. Dimensionless.
pub fn regularised_friction_share(slip: f64, eps: f64) -> f64 {
    slip / (slip * slip + eps * eps).sqrt()
}

// ---------------------------------------------------------------------------------------
// Geometry
// ---------------------------------------------------------------------------------------

/// The length (mm) of a circular arc of radius `radius` (mm) over the angle `angle` (rad):
/// `r θ`.
pub fn arc_length(radius: f64, angle: f64) -> f64 {
    radius * angle
}

/// The curvature (1/mm) of a circle of radius `radius` (mm), `1/r`: also each principal
/// curvature of a sphere of that radius, and the profile curvature of a torus's tube.
pub fn circle_curvature(radius: f64) -> f64 {
    1.0 / radius
}

/// The signed distance (mm) from `p` to the sphere of centre `centre` and radius `radius`:
/// `|p − c| − R`, positive outside.
pub fn sphere_distance(centre: [f64; 3], radius: f64, p: [f64; 3]) -> f64 {
    let d: f64 = (0..3).map(|m| (p[m] - centre[m]).powi(2)).sum();
    d.sqrt() - radius
}

/// How many woven cells cover a parallelogram with sides `sides` (mm) along the two yarns,
/// the yarns at `angle` (rad) to each other: its area `a b sin θ` over a cell's area
/// `L01 L02 sin θ`, i.e. `a b / (L01 L02)` whatever the angle.
pub fn cells_in_parallelogram(sides: [f64; 2], angle: f64, l0: [f64; 2]) -> f64 {
    sides[0] * sides[1] * angle.sin() / (l0[0] * l0[1] * angle.sin())
}

/// The force (N) on each of the two nodes of an element edge of length `edge` (mm) cut by
/// yarns `spacing` (mm) apart that each carry `tension` (N), in a homogeneous state: the
/// tension times the number of yarns crossing the edge, `T · edge / spacing`, shared equally.
pub fn edge_node_force(tension: f64, edge: f64, spacing: f64) -> f64 {
    tension * (edge / spacing) / 2.0
}

/// The deformation gradient of pure trellising (the shear of a pin-jointed net) by the angle
/// `gamma` (rad), warp along x, weft along y: the warp stays along x, the weft turns by γ,
/// and no yarn changes length (both columns of `F` stay unit vectors). The shear angle, the
/// change of the angle between the yarns, is γ itself.
pub fn pure_trellis(gamma: f64) -> [[f64; 3]; 3] {
    [
        [1.0, gamma.sin(), 0.0],
        [0.0, gamma.cos(), 0.0],
        [0.0, 0.0, 1.0],
    ]
}

// ---------------------------------------------------------------------------------------
// The woven cell (Boisse et al. 1997, eqs 1–5; `src/guide/theory.md`)
// ---------------------------------------------------------------------------------------

/// One reference point of the law: fabric strains, tensions and closure.
#[derive(Clone, Copy, Debug)]
pub struct LawReference {
    /// `[ε1, ε2]`, the fabric strains along warp and weft.
    pub eps: [f64; 2],
    /// `[T11, T22]`, N per yarn, printed with 4 decimals.
    pub t: [f64; 2],
    /// The closure `s = w1 − w2`, mm, printed with 6 decimals.
    pub closure: f64,
}

/// The law's reference values on the paper's glass fabric (the table in `src/guide/theory.md`),
/// worked out independently of the crate by nested bracketed scalar solves of the paper's equations (1)–(5), not by the
/// crate: k = 1 at 0.4 %, uniaxial warp strain at 1 %, k = 2 at 0.6 %.
pub const LAW_REFERENCE: [LawReference; 3] = [
    LawReference {
        eps: [0.004, 0.004],
        t: [96.5786, 96.5786],
        closure: 0.073713,
    },
    LawReference {
        eps: [0.010, 0.000],
        t: [230.8726, 88.7289],
        closure: 0.074658,
    },
    LawReference {
        eps: [0.006, 0.003],
        t: [135.2375, 100.3588],
        closure: 0.074407,
    },
];

/// The residuals of the paper's equations (1)–(5), written in the paper's own variables, at
/// fabric strains `eps`, crown displacements `w = [w1, w2]` (mm) and fabric tensions `t` (N):
/// `[vertical equilibrium (N), transverse compression (mm), T11 (N), T22 (N)]`. All four vanish
/// at the law's solution. With `λ = [−1, 1]`, `hα = e0α + λα wα`:
///
/// ```text
///   ℓα = sqrt(4 hα² + L0α² (1 + εα)²)      εfα = ℓα / sqrt(L0α² + 4 e0α²) − 1      (3)
///   Tfα = Cα max(εfα, 0)                                                          (1)
///   cos θα = 2 hα / ℓα, sin θα = L0α (1 + εα) / ℓα                                (4)
///   Tf1 cos θ1 = Tf2 cos θ2,  Tαα = Tfα sin θα,  Fc = 2 Tf1 cos θ1                 (5)
///   w1 − w2 = A (1 − exp(−B Fc))                                                  (2)
/// ```
pub fn paper_equation_residuals(
    p: &CellParams,
    eps: [f64; 2],
    w: [f64; 2],
    t: [f64; 2],
) -> [f64; 4] {
    let lambda = [-1.0, 1.0];
    let mut tf = [0.0; 2];
    let mut cos = [0.0; 2];
    let mut sin = [0.0; 2];
    for a in 0..2 {
        let h = p.e0[a] + lambda[a] * w[a];
        let len = (4.0 * h * h + p.l0[a].powi(2) * (1.0 + eps[a]).powi(2)).sqrt();
        let eps_f = len / (p.l0[a].powi(2) + 4.0 * p.e0[a].powi(2)).sqrt() - 1.0; // eq 3
        tf[a] = p.c[a] * eps_f.max(0.0); // eq 1
        cos[a] = 2.0 * h / len; // eq 4
        sin[a] = p.l0[a] * (1.0 + eps[a]) / len;
    }
    let fc = 2.0 * tf[0] * cos[0]; // eq 5
    [
        tf[0] * cos[0] - tf[1] * cos[1], // eq 5, vertical equilibrium
        (w[0] - w[1]) - p.a * (1.0 - (-p.b * fc).exp()), // eq 2
        t[0] - tf[0] * sin[0],           // eq 5, T11
        t[1] - tf[1] * sin[1],           // eq 5, T22
    ]
}

/// The symmetric cell (equal yarns, `ε1 = ε2 = eps`, k = 1) solved without the crate: by
/// symmetry both crowns sit at `h = e0 − s/2`, each yarn is a straight bar of doubled length
/// `ℓ = sqrt(4h² + L²)`, `L = L0 (1 + ε)`, with `V = 2 C h q`, `T = C L q`,
/// `q = 1/ℓ0 − 1/ℓ` (`ℓ0 = sqrt(L0² + 4 e0²)`), and the closure solves the scalar equation
/// `s = A (1 − exp(−2 B V))` by bisection on `[0, A]`. Returns `(T in N, s in mm)`.
pub fn symmetric_cell(p: CellParams, eps: f64) -> (f64, f64) {
    let (l0, e0, c) = (p.l0[0], p.e0[0], p.c[0]);
    let len0 = (l0 * l0 + 4.0 * e0 * e0).sqrt();
    let l = l0 * (1.0 + eps);
    let q = |s: f64| {
        let h = e0 - 0.5 * s;
        (1.0 / len0 - 1.0 / (4.0 * h * h + l * l).sqrt()).max(0.0)
    };
    let g = |s: f64| s - p.a * (1.0 - (-2.0 * p.b * 2.0 * c * (e0 - 0.5 * s) * q(s)).exp());
    let (mut lo, mut hi) = (0.0, p.a);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let s = 0.5 * (lo + hi);
    (c * l * q(s), s)
}

/// The symmetric cell once the closure has saturated (`s = A`) is linear-elastic in closed
/// form.
#[derive(Clone, Copy, Debug)]
pub struct SaturatedCell {
    /// `T = C L (1/ℓ0 − 1/ℓ)`, N per yarn.
    pub t: f64,
    /// `dT/dε = C L0 (1/ℓ0 − 1/ℓ + L²/ℓ³)` along k = 1, N.
    pub slope: f64,
    /// `sin²θ = L²/ℓ²`: the slope is `C sin²θ` up to terms of the order of the crimp.
    pub sin2: f64,
}

/// [`SaturatedCell`] of the symmetric cell at `ε1 = ε2 = eps`: `h = e0 − A/2`,
/// `L = L0 (1 + ε)`, `ℓ = sqrt(4h² + L²)`, `ℓ0 = sqrt(L0² + 4 e0²)` (the closure
/// saturates at A, after which the response is linear with slope ≈ Cα sin²θα: see
/// `src/guide/theory.md`).
pub fn saturated_symmetric_cell(p: CellParams, eps: f64) -> SaturatedCell {
    let (l0, e0, c, a) = (p.l0[0], p.e0[0], p.c[0], p.a);
    let len0 = (l0 * l0 + 4.0 * e0 * e0).sqrt();
    let h = e0 - 0.5 * a;
    let l = l0 * (1.0 + eps);
    let len = (4.0 * h * h + l * l).sqrt();
    SaturatedCell {
        t: c * l * (1.0 / len0 - 1.0 / len),
        slope: c * l0 * (1.0 / len0 - 1.0 / len + l * l / len.powi(3)),
        sin2: (l / len).powi(2),
    }
}

/// The linear yarn law of the paper's first example (undulation off): the fabric tension of
/// a yarn of stiffness `c` (N) at strain `eps` is `C max(ε, 0)` (N; yarns buckle, never push),
/// and its derivative `C` when taut, 0 when slack.
pub fn linear_yarn_tension(c: f64, eps: f64) -> (f64, f64) {
    if eps > 0.0 { (c * eps, c) } else { (0.0, 0.0) }
}

// ---------------------------------------------------------------------------------------
// Statistics, verdicts, the explorer's arithmetic
// ---------------------------------------------------------------------------------------

/// The root mean square of noise uniform on `[−half_width, half_width]`: `a / √3`.
pub fn uniform_rms(half_width: f64) -> f64 {
    half_width / 3f64.sqrt()
}

/// The verdict's definition (guide::scenes, `feasible`): a converged, sound design is feasible when
/// its largest shear (degrees) is within the locking angle and its largest yarn tension (N)
/// within the breaking tension. The paper's criterion is the first (Figure 11: "the maximum
/// value of these angular variations are close to 60°").
pub fn feasible(max_shear_deg: f64, locking_deg: f64, max_tension_n: f64, break_n: f64) -> bool {
    max_shear_deg <= locking_deg && max_tension_n <= break_n
}

/// The verdict with error bands (guide::scenes, `verdict`): the shear's band is `shear ± err_deg`,
/// the tension's `tension · (1 ± err_pct/100)`. `INFEASIBLE` when a band lies wholly over its
/// limit, `FEASIBLE` when both lie wholly under (or at) their limits, `MARGINAL` when a limit
/// lies inside a band.
pub fn verdict_word(
    (max_shear_deg, err_deg, locking_deg): (f64, f64, f64),
    (max_tension_n, err_pct, break_n): (f64, f64, f64),
) -> &'static str {
    let shear = [max_shear_deg - err_deg, max_shear_deg + err_deg];
    let e = err_pct / 100.0;
    let tension = [max_tension_n * (1.0 - e), max_tension_n * (1.0 + e)];
    if shear[0] > locking_deg || tension[0] > break_n {
        "INFEASIBLE"
    } else if shear[1] <= locking_deg && tension[1] <= break_n {
        "FEASIBLE"
    } else {
        "MARGINAL"
    }
}

/// A run's estimated time left (s) at a constant pace: `done` of `total` designs in
/// `elapsed_s` seconds leave `(total − done) · elapsed / done`.
pub fn eta_s(done: usize, total: usize, elapsed_s: f64) -> f64 {
    (total - done) as f64 * elapsed_s / done as f64
}
