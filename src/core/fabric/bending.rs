//! Bending stiffness of the fabric (beyond the paper, which leaves it out on purpose): a
//! rotation-free hinge at every interior node of every yarn line of a yarn-grid blank.
//!
//! A hinge joins the node `x1` to its neighbours `x0` and `x2` along one yarn line; with
//! `e1 = x1 − x0`, `e2 = x2 − x1` and `c = cos φ = ê1·ê2` (`φ` the turning angle),
//!
//! ```text
//!   energy  k (1 − cos φ),   k = B w / L̄
//! ```
//!
//! `B` the bending rigidity per unit width (N·mm), `w` the width of fabric the yarn line stands
//! for (the spacing of its neighbouring lines, halved at a free edge), `L̄` the mean of the two
//! initial segment lengths. For small turning angles `1 − cos φ ≈ φ²/2` and the curvature is
//! `φ/L̄`, so the energy is `½ B w κ² L̄`, the elastica's `∫ ½ B κ² ds` over the hinge's share of
//! the line. A straight line stores nothing; the energy depends on the segments' directions
//! only, so a rigid motion changes nothing. The dofs stay the nodes' positions: no rotations.
//!
//! With `a = |e1|`, `b = |e2|`, `P1 = I − ê1ê1ᵀ`, `g1 = ∂c/∂e1 = (ê2 − c ê1)/a`,
//! `g2 = ∂c/∂e2 = (ê1 − c ê2)/b`:
//!
//! ```text
//!   ∂²c/∂e1²    = −(ê1 g1ᵀ + g1 ê1ᵀ)/a − c P1/a²
//!   ∂²c/∂e2²    = −(ê2 g2ᵀ + g2 ê2ᵀ)/b − c P2/b²
//!   ∂²c/∂e1∂e2  = (P2/b − ê1 g2ᵀ)/a
//! ```
//!
//! and `x0, x1, x2` enter through `e1 = x1 − x0`, `e2 = x2 − x1`.

/// One hinge: three consecutive nodes of a yarn line and its stiffness `k = B w / L̄` (N·mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hinge {
    pub nodes: [usize; 3],
    pub k: f64,
}

/// A hinge's energy (N·mm), its gradient (N, `[3·node + m]` over its three nodes) and, when
/// asked, its Hessian (N/mm).
#[derive(Clone, Copy, Debug)]
pub struct HingeResponse {
    pub energy: f64,
    pub f: [f64; 9],
    pub k: [[f64; 9]; 9],
}

impl Default for HingeResponse {
    fn default() -> Self {
        HingeResponse {
            energy: 0.0,
            f: [0.0; 9],
            k: [[0.0; 9]; 9],
        }
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The hinge of stiffness `k` at positions `x` (mm); the Hessian when `tangent`. A segment of
/// zero length has no direction: such a hinge stores nothing.
pub fn evaluate(k: f64, x: [[f64; 3]; 3], tangent: bool) -> HingeResponse {
    let mut out = HingeResponse::default();
    let (e1, e2) = (sub(x[1], x[0]), sub(x[2], x[1]));
    let (a, b) = (dot(e1, e1).sqrt(), dot(e2, e2).sqrt());
    if a == 0.0 || b == 0.0 {
        return out;
    }
    let (u1, u2) = (e1.map(|v| v / a), e2.map(|v| v / b));
    let c = dot(u1, u2);
    out.energy = k * (1.0 - c);
    let g1: [f64; 3] = std::array::from_fn(|m| (u2[m] - c * u1[m]) / a);
    let g2: [f64; 3] = std::array::from_fn(|m| (u1[m] - c * u2[m]) / b);
    // E = k(1 − c): ∂E/∂x0 = k g1, ∂E/∂x1 = −k (g1 − g2), ∂E/∂x2 = −k g2.
    for m in 0..3 {
        out.f[m] = k * g1[m];
        out.f[3 + m] = -k * (g1[m] - g2[m]);
        out.f[6 + m] = -k * g2[m];
    }
    if !tangent {
        return out;
    }
    // Hessian of c with respect to (e1, e2).
    let mut h11 = [[0.0; 3]; 3];
    let mut h22 = [[0.0; 3]; 3];
    let mut h12 = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let d = (i == j) as u8 as f64;
            h11[i][j] = -(u1[i] * g1[j] + g1[i] * u1[j]) / a - c * (d - u1[i] * u1[j]) / (a * a);
            h22[i][j] = -(u2[i] * g2[j] + g2[i] * u2[j]) / b - c * (d - u2[i] * u2[j]) / (b * b);
            h12[i][j] = ((d - u2[i] * u2[j]) / b - u1[i] * g2[j]) / a;
        }
    }
    // e1 = x1 − x0, e2 = x2 − x1: the node blocks of −k ∂²c/∂x∂x.
    let s = [[-1.0, 0.0], [1.0, -1.0], [0.0, 1.0]];
    for p in 0..3 {
        for q in 0..3 {
            for i in 0..3 {
                for j in 0..3 {
                    let v = s[p][0] * s[q][0] * h11[i][j]
                        + s[p][1] * s[q][1] * h22[i][j]
                        + s[p][0] * s[q][1] * h12[i][j]
                        + s[p][1] * s[q][0] * h12[j][i];
                    out.k[3 * p + i][3 * q + j] = -k * v;
                }
            }
        }
    }
    out
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// The hinges along yarn lines given as node sequences (any mesh whose yarns run through its
/// nodes, such as the bias specimen's diamonds), rigidity `b` (N·mm per unit width) for every
/// line: at each interior node the line stands for the width `A / L̄` of fabric (`A` the node's
/// share of the initial area, `L̄` the mean of its two initial segment lengths), so
/// `k = b A / L̄²`; on a yarn grid that is [`crate::core::membrane::hinges::yarn_hinges`]'s `b w / L̄`.
pub fn line_hinges(nodes: &[[f64; 3]], lines: &[Vec<usize>], area: &[f64], b: f64) -> Vec<Hinge> {
    let len = |a: usize, c: usize| norm(sub(nodes[c], nodes[a]));
    let mut hinges = Vec::new();
    for line in lines {
        for w in line.windows(3) {
            let l = 0.5 * (len(w[0], w[1]) + len(w[1], w[2]));
            if l > 0.0 && b > 0.0 {
                hinges.push(Hinge {
                    nodes: [w[0], w[1], w[2]],
                    k: b * area[w[1]] / (l * l),
                });
            }
        }
    }
    hinges
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::membrane::hinges::yarn_hinges;
    use crate::core::membrane::mesh::Mesh;

    fn bent() -> [[f64; 3]; 3] {
        [[0.0, 0.0, 0.0], [2.1, 0.3, 0.4], [3.9, 1.4, -0.2]]
    }

    #[test]
    fn line_hinges_on_a_yarn_grid_are_its_yarn_hinges() {
        let mesh = Mesh::yarn_grid([0.0, 0.0], [12.0, 6.0], [6, 3], std::f64::consts::FRAC_PI_2);
        let area = crate::core::membrane::mesh::tributary_areas(&mesh);
        let id = |i: usize, j: usize| j * 7 + i;
        let warp: Vec<Vec<usize>> = (0..=3)
            .map(|j| (0..=6).map(|i| id(i, j)).collect())
            .collect();
        let weft: Vec<Vec<usize>> = (0..=6)
            .map(|i| (0..=3).map(|j| id(i, j)).collect())
            .collect();
        let mut by_lines = line_hinges(&mesh.nodes, &warp, &area, 0.3);
        by_lines.extend(line_hinges(&mesh.nodes, &weft, &area, 0.5));
        let by_grid = yarn_hinges(&mesh, [0.3, 0.5]).unwrap();
        assert_eq!(by_lines.len(), by_grid.len());
        for h in &by_grid {
            let same = by_lines.iter().find(|g| g.nodes == h.nodes).unwrap();
            assert!((same.k - h.k).abs() < 1e-12 * h.k, "{:?} {:?}", same, h);
        }
    }

    #[test]
    fn force_and_tangent_are_the_energys_derivatives() {
        let (k, x, h) = (0.7, bent(), 1e-6);
        let r = evaluate(k, x, true);
        for d in 0..9 {
            let mut xp = x;
            let mut xm = x;
            xp[d / 3][d % 3] += h;
            xm[d / 3][d % 3] -= h;
            let (rp, rm) = (evaluate(k, xp, false), evaluate(k, xm, false));
            let fd = (rp.energy - rm.energy) / (2.0 * h);
            assert!(
                (r.f[d] - fd).abs() < 1e-7,
                "force {d}: {} against {fd}",
                r.f[d]
            );
            for e in 0..9 {
                let kd = (rp.f[e] - rm.f[e]) / (2.0 * h);
                assert!(
                    (r.k[e][d] - kd).abs() < 1e-6,
                    "tangent {e},{d}: {} against {kd}",
                    r.k[e][d]
                );
            }
        }
    }

    #[test]
    fn a_straight_line_stores_nothing_and_a_rigid_motion_changes_nothing() {
        let straight = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.5, 2.5, 2.5]];
        let r = evaluate(3.0, straight, true);
        assert!(r.energy.abs() < 1e-15 && r.f.iter().all(|v| v.abs() < 1e-12));
        // A rotation about an oblique axis and a translation.
        let (s, c) = (0.9f64.sin(), 0.9f64.cos());
        let rot = |p: [f64; 3]| {
            [
                c * p[0] - s * p[1] + 5.0,
                s * p[0] + c * p[1] - 2.0,
                p[2] + 7.0,
            ]
        };
        let x = bent();
        let (a, b) = (evaluate(0.7, x, false), evaluate(0.7, x.map(rot), false));
        assert!((a.energy - b.energy).abs() < 1e-12);
        // Forces balance: no net force on a hinge.
        for m in 0..3 {
            assert!((a.f[m] + a.f[3 + m] + a.f[6 + m]).abs() < 1e-12);
        }
    }

    #[test]
    fn small_angles_give_the_elasticas_energy() {
        // A circular arc of curvature κ through three nodes 1 mm apart: E = ½ B w κ² L̄.
        let (bw, kappa, l): (f64, f64, f64) = (2.0, 0.01, 1.0);
        let phi = kappa * l;
        let x = [
            [-l, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [l * phi.cos(), l * phi.sin(), 0.0],
        ];
        let e = evaluate(bw / l, x, false).energy;
        let elastica = 0.5 * bw * kappa * kappa * l;
        assert!((e / elastica - 1.0).abs() < 1e-4, "{e} against {elastica}");
    }

    #[test]
    fn a_grid_gets_a_hinge_at_every_interior_node_of_every_line() {
        let mesh = Mesh::yarn_grid([0.0, 0.0], [10.0, 4.0], [5, 2], std::f64::consts::FRAC_PI_2);
        let hinges = yarn_hinges(&mesh, [1.0, 2.0]).unwrap();
        // Warp: 3 lines × 4 interior nodes; weft: 6 lines × 1.
        assert_eq!(hinges.len(), 3 * 4 + 6);
        // An interior warp line stands for 2 mm of width, its edge lines for 1 mm; L̄ = 2 mm.
        let k: Vec<f64> = hinges.iter().take(12).map(|h| h.k).collect();
        assert!((k[0] - 1.0 * 1.0 / 2.0).abs() < 1e-12 && (k[4] - 1.0 * 2.0 / 2.0).abs() < 1e-12);
        // A weft off the grid's lines: the yarn lines are not the mesh's lines.
        let mut skew = mesh.clone();
        skew.yarns = Some([[1.0, 0.0, 0.0], [0.5, 0.75f64.sqrt(), 0.0]]);
        assert!(yarn_hinges(&skew, [1.0, 1.0]).is_none());
    }
}
