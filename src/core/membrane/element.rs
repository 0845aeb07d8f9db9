//! The 4-node woven-cell membrane element (paper eqs 18–47).
//!
//! Bilinear interpolation (eq 18), three displacement dofs a node. The element is made of woven
//! cells whose warp and weft run along the unit yarn vectors `hα0` of the initial configuration.
//! Writing `hα0 = aα^β gβ0` with the contravariant components `aα^β = hα0 · g^β0` (eq 21), the
//! derivative along yarn α is `dα = aα^β ∂/∂ξβ`, and the current image of the unit yarn vector is
//!
//! ```text
//!   fα = Σk dαN^k x^k,       Eαα = ½(|fα|² − 1),       1 + εα = |fα|
//! ```
//!
//! (the Green–Lagrange strain along the yarn, Appendix A; the exact stretch: [`crate::guide::theory`]). When
//! the element's natural directions are the yarns, `aα^β = δα^β/|gα0|` and `Eαα = Ēαα/|gα0|²`: the
//! paper's element. With `S̃α = L0α Tαα/(1+εα)` (the resultant paired with `δEαα`) and `n` cells at a
//! Gauss point:
//!
//! ```text
//!   internal force (eq 35)       F  = n Σα S̃α Bα,                 Bα[k,m] = dαN^k fα[m]
//!   geometric stiffness (eq 41)  Kσ = n Σα S̃α dαN^k dαN^q δmn
//!   material stiffness (eq 47)   K  = n Σαβ Dαβ Bα Bβᵀ,           Dαβ = ∂S̃α/∂Eββ
//! ```
//!
//! The number of cells of the element is its initial area over the cell area `L01 L02 sin φ0`
//! (fractional allowed), shared among the 2×2 Gauss points by their weights.

use crate::core::fabric::law::{CellLaw, CellResponse, CrimpState};

/// Gauss points of the element (2×2).
pub const GAUSS: usize = 4;
const G: f64 = 0.577_350_269_189_625_8; // 1/sqrt(3)
const GAUSS_XI: [[f64; 2]; GAUSS] = [[-G, -G], [G, -G], [G, G], [-G, G]];

/// `∂N^k/∂ξβ` at `ξ` (eq 18), `[k][β]`.
pub fn shape_derivatives(xi: [f64; 2]) -> [[f64; 2]; 4] {
    let (a, b) = (xi[0], xi[1]);
    [
        [-0.25 * (1.0 - b), -0.25 * (1.0 - a)],
        [0.25 * (1.0 - b), -0.25 * (1.0 + a)],
        [0.25 * (1.0 + b), 0.25 * (1.0 + a)],
        [-0.25 * (1.0 + b), 0.25 * (1.0 - a)],
    ]
}

/// What the element needs from its initial configuration, computed once.
#[derive(Clone, Copy, Debug)]
pub struct ElementGeometry {
    /// `dαN^k` at each Gauss point: `[gp][α][k]`, 1/mm.
    pub d: [[[f64; 4]; 2]; GAUSS],
    /// Woven cells represented by each Gauss point.
    pub cells: [f64; GAUSS],
    /// `dαN^k` at the centre, for the shear angle.
    pub d_centre: [[f64; 4]; 2],
    /// Initial angle between warp and weft, rad.
    pub yarn_angle0: f64,
    /// Initial area, mm².
    pub area0: f64,
    /// At each Gauss point: the initial angle between the yarns (rad) and the initial area it
    /// stands for (mm²), for the shear law.
    pub theta0: [f64; GAUSS],
    pub area_gp: [f64; GAUSS],
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Why an element cannot be built.
#[derive(Clone, Debug, PartialEq)]
pub enum GeometryError {
    /// The element is degenerate or inverted at a Gauss point.
    Degenerate,
    /// A yarn direction is (nearly) normal to the element.
    YarnOutOfPlane,
}

/// Covariant vectors `g1, g2` at `ξ` from nodal positions.
fn covariant(x: &[[f64; 3]; 4], dn: &[[f64; 2]; 4]) -> [[f64; 3]; 2] {
    let mut g = [[0.0; 3]; 2];
    for k in 0..4 {
        for beta in 0..2 {
            for m in 0..3 {
                g[beta][m] += dn[k][beta] * x[k][m];
            }
        }
    }
    g
}

/// The yarn directions at one point of the initial element.
struct YarnFrame {
    /// `dαN^k`, 1/mm.
    d: [[f64; 4]; 2],
    /// `|g10 × g20|`, mm².
    det_j: f64,
    /// Angle between warp and weft, rad.
    yarn_angle: f64,
}

impl YarnFrame {
    fn at(
        x0: &[[f64; 3]; 4],
        xi: [f64; 2],
        yarns: Option<[[f64; 3]; 2]>,
    ) -> Result<YarnFrame, GeometryError> {
        let dn = shape_derivatives(xi);
        let g = covariant(x0, &dn);
        let normal = cross(g[0], g[1]);
        let det_j = norm(normal);
        let scale = norm(g[0]) * norm(g[1]);
        if det_j.is_nan() || det_j <= 1e-12 * scale || !det_j.is_finite() {
            return Err(GeometryError::Degenerate);
        }
        let nn = [normal[0] / det_j, normal[1] / det_j, normal[2] / det_j];
        // Metric and its inverse.
        let m = [
            [dot(g[0], g[0]), dot(g[0], g[1])],
            [dot(g[1], g[0]), dot(g[1], g[1])],
        ];
        let det_m = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        let inv = [
            [m[1][1] / det_m, -m[0][1] / det_m],
            [-m[1][0] / det_m, m[0][0] / det_m],
        ];
        let mut d = [[0.0; 4]; 2];
        let mut h_in_plane = [[0.0; 3]; 2];
        for alpha in 0..2 {
            // The yarn projected on the tangent plane and normalised (or the natural direction).
            let h = yarns.map_or(g[alpha], |y| y[alpha]);
            let hn = dot(h, nn);
            let hp = [h[0] - hn * nn[0], h[1] - hn * nn[1], h[2] - hn * nn[2]];
            let len = norm(hp);
            if len < 1e-6 * norm(h) || len == 0.0 {
                return Err(GeometryError::YarnOutOfPlane);
            }
            let hp = [hp[0] / len, hp[1] / len, hp[2] / len];
            h_in_plane[alpha] = hp;
            // Contravariant components aα^β = G^βγ (gγ · hα).
            let gh = [dot(g[0], hp), dot(g[1], hp)];
            let a = [
                inv[0][0] * gh[0] + inv[0][1] * gh[1],
                inv[1][0] * gh[0] + inv[1][1] * gh[1],
            ];
            for k in 0..4 {
                d[alpha][k] = a[0] * dn[k][0] + a[1] * dn[k][1];
            }
        }
        let yarn_angle = dot(h_in_plane[0], h_in_plane[1]).clamp(-1.0, 1.0).acos();
        Ok(YarnFrame {
            d,
            det_j,
            yarn_angle,
        })
    }
}

impl ElementGeometry {
    /// Builds the element from its initial nodes (counter-clockwise), the yarn directions (unit
    /// vectors, projected on the element's tangent plane; `None`: along the element's natural
    /// directions, the paper's element) and the cell lengths' product `L01 L02` (mm²).
    pub fn new(
        x0: &[[f64; 3]; 4],
        yarns: Option<[[f64; 3]; 2]>,
        cell_lengths: f64,
    ) -> Result<Self, GeometryError> {
        let mut d = [[[0.0; 4]; 2]; GAUSS];
        let mut cells = [0.0; GAUSS];
        let mut area0 = 0.0;
        let mut theta0 = [0.0; GAUSS];
        let mut area_gp = [0.0; GAUSS];
        for (gp, xi) in GAUSS_XI.iter().enumerate() {
            let at = YarnFrame::at(x0, *xi, yarns)?;
            d[gp] = at.d;
            theta0[gp] = at.yarn_angle;
            area_gp[gp] = at.det_j;
            // Gauss weights are 1 for the 2×2 rule on [−1, 1]².
            area0 += at.det_j;
            cells[gp] = at.det_j / (cell_lengths * at.yarn_angle.sin().abs());
        }
        let centre = YarnFrame::at(x0, [0.0, 0.0], yarns)?;
        Ok(ElementGeometry {
            d,
            cells,
            d_centre: centre.d,
            yarn_angle0: centre.yarn_angle,
            area0,
            theta0,
            area_gp,
        })
    }

    /// Number of woven cells in the element.
    pub fn cell_count(&self) -> f64 {
        self.cells.iter().sum()
    }
}

/// `fα = Σk dαN^k x^k` for both yarns.
#[inline]
fn yarn_images(d: &[[f64; 4]; 2], x: &[[f64; 3]; 4]) -> [[f64; 3]; 2] {
    let mut f = [[0.0; 3]; 2];
    for alpha in 0..2 {
        for k in 0..4 {
            let c = d[alpha][k];
            f[alpha][0] += c * x[k][0];
            f[alpha][1] += c * x[k][1];
            f[alpha][2] += c * x[k][2];
        }
    }
    f
}

/// The shear angle at the element centre: the change of the warp–weft angle, degrees
/// (positive when the angle closes).
pub fn shear_angle_deg(geo: &ElementGeometry, x: &[[f64; 3]; 4]) -> f64 {
    let f = yarn_images(&geo.d_centre, x);
    let (n0, n1) = (norm(f[0]), norm(f[1]));
    if n0 <= 0.0 || n1 <= 0.0 {
        return 0.0;
    }
    let angle = (dot(f[0], f[1]) / (n0 * n1)).clamp(-1.0, 1.0).acos();
    (geo.yarn_angle0 - angle).to_degrees()
}

/// The element's contribution at a configuration.
#[derive(Clone, Debug)]
pub struct ElementOutput {
    /// Internal force, N, `[3k + m]`.
    pub f: [f64; 12],
    /// Tangent `K + Kσ`, N/mm (full, symmetric).
    pub k: [[f64; 12]; 12],
    /// Stored energy, N·mm.
    pub energy: f64,
    /// Tensions `[gp][α]`, N per yarn.
    pub tension: [[f64; 2]; GAUSS],
    /// Law Newton iterations summed over the Gauss points.
    pub law_iterations: u32,
}

impl Default for ElementOutput {
    fn default() -> Self {
        ElementOutput {
            f: [0.0; 12],
            k: [[0.0; 12]; 12],
            energy: 0.0,
            tension: [[0.0; 2]; GAUSS],
            law_iterations: 0,
        }
    }
}

/// Internal force, tangent (if `tangent`) and energy at the current nodal positions `x`;
/// `crimp` (one state per Gauss point) is the warm start and receives the solved state.
///
/// The material stiffness is summed over the Gauss points as one product: with the eight
/// vectors `Bα` of the four points as the columns of `B` (12×8) and `W` holding each point's
/// `Dαβ`, `K = B W Bᵀ`, each entry a dot product of length 8 written once.
pub fn evaluate(
    geo: &ElementGeometry,
    law: &CellLaw,
    x: &[[f64; 3]; 4],
    crimp: &mut [CrimpState; GAUSS],
    tangent: bool,
    out: &mut ElementOutput,
) {
    out.f = [0.0; 12];
    out.energy = 0.0;
    out.law_iterations = 0;
    let l0 = law.p.l0;
    // Row i: the components i of the eight vectors Bα (columns 2·gp + α), and of W Bᵀ.
    let mut bt = [[0.0; 2 * GAUSS]; 12];
    let mut wbt = [[0.0; 2 * GAUSS]; 12];
    // Geometric stiffness per node pair: Σ S̃α dαN^k dαN^q.
    let mut geometric = [[0.0; 4]; 4];
    // The shear law's tangent (upper triangle filled at the end), when there is one.
    let mut k_shear = [[0.0; 12]; 12];
    for gp in 0..GAUSS {
        let d = &geo.d[gp];
        let n = geo.cells[gp];
        let f = yarn_images(d, x);
        if let Some(law) = &law.shear {
            let a = geo.area_gp[gp];
            out.energy += add_shear(law, (d, &f, geo.theta0[gp], a), tangent, out, &mut k_shear);
        }
        let stretch = [norm(f[0]), norm(f[1])];
        let eps = [stretch[0] - 1.0, stretch[1] - 1.0];
        let r = law.evaluate(eps, crimp[gp]);
        crimp[gp] = r.crimp;
        out.tension[gp] = r.t;
        out.law_iterations += r.iterations;
        if r.t[0] != 0.0 || r.t[1] != 0.0 {
            out.energy += n * law.energy(eps, r.crimp);
        }
        // S̃α = L0α Tαα / (1 + εα): the resultant paired with δEαα, times the cell count.
        let mut s = [0.0; 2];
        for alpha in 0..2 {
            if stretch[alpha] > 0.0 {
                s[alpha] = n * l0[alpha] * r.t[alpha] / stretch[alpha];
            }
        }
        // Bα[3k+m] = dαN^k fα[m].
        let mut b = [[0.0; 12]; 2];
        for alpha in 0..2 {
            for k in 0..4 {
                for m in 0..3 {
                    b[alpha][3 * k + m] = d[alpha][k] * f[alpha][m];
                }
            }
            for i in 0..12 {
                out.f[i] += s[alpha] * b[alpha][i];
            }
        }
        if !tangent {
            continue;
        }
        let dm = material_tangent(&r, stretch, n, l0);
        for i in 0..12 {
            bt[i][2 * gp] = b[0][i];
            bt[i][2 * gp + 1] = b[1][i];
            wbt[i][2 * gp] = dm[0][0] * b[0][i] + dm[0][1] * b[1][i];
            wbt[i][2 * gp + 1] = dm[1][0] * b[0][i] + dm[1][1] * b[1][i];
        }
        for k in 0..4 {
            for q in k..4 {
                geometric[k][q] += s[0] * d[0][k] * d[0][q] + s[1] * d[1][k] * d[1][q];
            }
        }
    }
    if tangent {
        assemble_tangent(&bt, &wbt, &geometric, &k_shear, &mut out.k);
    }
}

/// `Dαβ = ∂S̃α/∂Eββ = n L0α [∂Tα/∂εβ / ((1+εα)(1+εβ)) − δαβ Tα/(1+εα)³]` at a Gauss point of
/// `n` cells, symmetrised (the weighted law tangent's asymmetry is round-off).
#[inline]
fn material_tangent(r: &CellResponse, stretch: [f64; 2], n: f64, l0: [f64; 2]) -> [[f64; 2]; 2] {
    let mut dm = [[0.0; 2]; 2];
    for alpha in 0..2 {
        for beta in 0..2 {
            if stretch[alpha] <= 0.0 || stretch[beta] <= 0.0 {
                continue;
            }
            let mut v = r.dt[alpha][beta] / (stretch[alpha] * stretch[beta]);
            if alpha == beta {
                v -= r.t[alpha] / stretch[alpha].powi(3);
            }
            dm[alpha][beta] = n * l0[alpha] * v;
        }
    }
    let d12 = 0.5 * (dm[0][1] + dm[1][0]);
    dm[0][1] = d12;
    dm[1][0] = d12;
    dm
}

/// The element tangent `K = Σ Bᵀ D B + geometric + shear` from the columns gathered over the
/// Gauss points (`bt`, `wbt` = D-weighted), the node pairs' geometric stiffness and the shear
/// law's upper triangle.
#[inline]
fn assemble_tangent(
    bt: &[[f64; 2 * GAUSS]; 12],
    wbt: &[[f64; 2 * GAUSS]; 12],
    geometric: &[[f64; 4]; 4],
    k_shear: &[[f64; 12]; 12],
    k: &mut [[f64; 12]; 12],
) {
    for i in 0..12 {
        for j in i..12 {
            let mut v = 0.0;
            for c in 0..2 * GAUSS {
                v += wbt[i][c] * bt[j][c];
            }
            if i % 3 == j % 3 {
                v += geometric[i / 3][j / 3];
            }
            v += k_shear[i][j];
            k[i][j] = v;
            k[j][i] = v;
        }
    }
}

/// Adds the shear law's force (and tangent, to `k`) at one Gauss point: `d` its `dαN^k`, `f`
/// the yarn images, `theta0` the initial yarn angle (rad), `area` the initial area (mm²) it
/// stands for. Returns the energy, N·mm.
///
/// ```text
///   F[3k+m] = A M(γ) Gk,m,        Gk,m = Σα dαN^k ∂γ/∂fα[m]
///   K = A [M'(γ) G Gᵀ + M(γ) Σαβ dαN^k dβN^q ∂²γ/∂fα[m]∂fβ[n]]
/// ```
fn add_shear(
    law: &crate::core::fabric::shear::ShearLaw,
    (d, f, theta0, area): (&[[f64; 4]; 2], &[[f64; 3]; 2], f64, f64),
    tangent: bool,
    out: &mut ElementOutput,
    k: &mut [[f64; 12]; 12],
) -> f64 {
    let kin = crate::core::fabric::shear::shear_kinematics(f, theta0, tangent);
    let g = kin.gamma;
    let m = area * law.moment(g);
    let mut grad = [0.0; 12];
    for node in 0..4 {
        for c in 0..3 {
            grad[3 * node + c] = d[0][node] * kin.grad[0][c] + d[1][node] * kin.grad[1][c];
        }
    }
    for i in 0..12 {
        out.f[i] += m * grad[i];
    }
    if tangent {
        let stiff = area * law.stiffness(g);
        for i in 0..12 {
            for j in i..12 {
                let (kn, mc, qn, nc) = (i / 3, i % 3, j / 3, j % 3);
                let mut h = 0.0;
                for a in 0..2 {
                    for b in 0..2 {
                        h += d[a][kn] * d[b][qn] * kin.hess[a][b][mc][nc];
                    }
                }
                k[i][j] += stiff * grad[i] * grad[j] + m * h;
            }
        }
    }
    area * law.energy(g)
}

/// The element's least principal membrane force, N per mm of initial length: the smaller
/// eigenvalue of `Σgp [Σα (S̃α fα + A M(γ) ∂γ/∂fα) ⊗ fα] / A0` (the yarns' resultants and the
/// shear law's moment, in the fabric's tangent plane), from the Gauss points' `tension`.
/// Positive: the fabric is stretched in every direction of its plane (taut), and a membrane
/// that is taut cannot wrinkle (tension field theory); at or below zero it is compressed in
/// some direction, or slack.
pub fn least_membrane_force_n_per_mm(
    geo: &ElementGeometry,
    law: &CellLaw,
    x: &[[f64; 3]; 4],
    tension: &[[f64; 2]; GAUSS],
) -> f64 {
    use crate::core::vec3::{sub, unit};
    let centre = yarn_images(&geo.d_centre, x);
    let e1 = unit(centre[0]);
    let along = sub(centre[1], e1.map(|v| v * dot(centre[1], e1)));
    if norm(e1) == 0.0 || norm(along) == 0.0 || geo.area0 <= 0.0 {
        return 0.0;
    }
    let e2 = unit(along);
    // τ projected on (e1, e2): Σ (force on the yarn image)·e_i (fα·e_j).
    let mut tau = [[0.0; 2]; 2];
    for gp in 0..GAUSS {
        let f = yarn_images(&geo.d[gp], x);
        let shear = law.shear.as_ref().map(|s| {
            let kin = crate::core::fabric::shear::shear_kinematics(&f, geo.theta0[gp], false);
            (geo.area_gp[gp] * s.moment(kin.gamma), kin.grad)
        });
        for alpha in 0..2 {
            let stretch = norm(f[alpha]);
            if stretch <= 0.0 {
                continue;
            }
            let s = geo.cells[gp] * law.p.l0[alpha] * tension[gp][alpha] / stretch;
            let force = match shear {
                Some((m, grad)) => [0, 1, 2].map(|c| s * f[alpha][c] + m * grad[alpha][c]),
                None => f[alpha].map(|v| s * v),
            };
            let (fe, ge) = (
                [dot(force, e1), dot(force, e2)],
                [dot(f[alpha], e1), dot(f[alpha], e2)],
            );
            for i in 0..2 {
                for j in 0..2 {
                    tau[i][j] += fe[i] * ge[j];
                }
            }
        }
    }
    let (a, d, b) = (tau[0][0], tau[1][1], 0.5 * (tau[0][1] + tau[1][0]));
    let least = 0.5 * (a + d) - (0.25 * (a - d) * (a - d) + b * b).sqrt();
    least / geo.area0
}
