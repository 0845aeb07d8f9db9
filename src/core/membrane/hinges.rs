//! The bending hinges of a yarn-grid blank: one at each interior node of each warp and weft
//! line, with the stiffness its share of the fabric's rigidity gives (the law is
//! [`crate::core::fabric::bending`]'s).

use crate::core::fabric::bending::Hinge;
use crate::core::membrane::mesh::Mesh;
use crate::core::vec3::{cross, dot, sub, unit};

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// The hinges of a yarn-grid blank (`mesh.grid`) for bending rigidities `[B1, B2]` (N·mm, per
/// unit width; warp along the grid's first index, weft along its second). `None` for a mesh
/// that is not a yarn grid, or whose grid lines do not run along its yarns (a weft off 90° on
/// a rectangular grid): its yarn lines are not known.
pub fn yarn_hinges(mesh: &Mesh, rigidity: [f64; 2]) -> Option<Vec<Hinge>> {
    let [n1, n2] = mesh.grid?;
    let id = |i: usize, j: usize| j * (n1 + 1) + i;
    let x = &mesh.nodes;
    if let Some(yarns) = mesh.yarns {
        let along = |a: usize, b: usize, h: [f64; 3]| {
            let e = sub(x[b], x[a]);
            (dot(e, h) / norm(e) - 1.0).abs() < 1e-9
        };
        if !(along(id(0, 0), id(1, 0), yarns[0]) && along(id(0, 0), id(0, 1), yarns[1])) {
            return None;
        }
    }
    // The sine of the angle between the yarns: the width across a line per unit spacing.
    let sine = mesh.yarns.map_or(1.0, |[h1, h2]| norm(cross(h1, h2)));
    Some(line_hinges(mesh, [n1, n2], rigidity, sine))
}

/// The hinges along an `[n1, n2]` grid's lines with rigidities `[B1, B2]` along its first and
/// second lines; `sine` the sine of the angle between them (the width across a line per unit
/// spacing).
fn line_hinges(mesh: &Mesh, [n1, n2]: [usize; 2], rigidity: [f64; 2], sine: f64) -> Vec<Hinge> {
    let id = |i: usize, j: usize| j * (n1 + 1) + i;
    let x = &mesh.nodes;
    let len = |a: usize, b: usize| norm(sub(x[b], x[a]));
    let mut hinges = Vec::new();
    // Warp lines: j fixed, i runs; their width is the spacing to the weft neighbours.
    for j in 0..=n2 {
        for i in 1..n1 {
            let below = if j > 0 {
                len(id(i, j - 1), id(i, j))
            } else {
                0.0
            };
            let above = if j < n2 {
                len(id(i, j), id(i, j + 1))
            } else {
                0.0
            };
            let w = 0.5 * (below + above) * sine;
            let l = 0.5 * (len(id(i - 1, j), id(i, j)) + len(id(i, j), id(i + 1, j)));
            hinges.push(Hinge {
                nodes: [id(i - 1, j), id(i, j), id(i + 1, j)],
                k: rigidity[0] * w / l,
            });
        }
    }
    for i in 0..=n1 {
        for j in 1..n2 {
            let left = if i > 0 {
                len(id(i - 1, j), id(i, j))
            } else {
                0.0
            };
            let right = if i < n1 {
                len(id(i, j), id(i + 1, j))
            } else {
                0.0
            };
            let w = 0.5 * (left + right) * sine;
            let l = 0.5 * (len(id(i, j - 1), id(i, j)) + len(id(i, j), id(i, j + 1)));
            hinges.push(Hinge {
                nodes: [id(i, j - 1), id(i, j), id(i, j + 1)],
                k: rigidity[1] * w / l,
            });
        }
    }
    hinges.retain(|h| h.k > 0.0);
    hinges
}

/// The bending rigidities along a grid's two lines (N·mm per unit width) of a fabric whose yarns
/// `yarns` do not run along them, from each yarn family's own `[B1, B2]`: a cylindrical bend of
/// curvature `κ` along a unit direction `d` curves yarn α by `κ (hα·d)²`, which stores
/// `½ Bα κ² (hα·d)⁴`; a line along `d` carries that bend alone, so its rigidity is
/// `Σα Bα (hα·d)⁴`. Exact for bends along the lines and, at 90° (`[B1, B2]`), for every bend;
/// a bend between the lines stores 0.67–1.48 times its energy with the yarns at 80° to each
/// other, 0.33–3.1 times at 60° (equal rigidities, over every direction of the bend): near 90°
/// an approximation, far from it a rough one, until the mesh runs along the yarns.
pub fn rigidity_along_lines(
    lines: [[f64; 3]; 2],
    yarns: [[f64; 3]; 2],
    rigidity: [f64; 2],
) -> [f64; 2] {
    lines.map(|d| (0..2).map(|a| rigidity[a] * dot(yarns[a], d).powi(4)).sum())
}

/// The hinges of a yarn-grid blank whose yarns are off its lines (a weft off 90° on a
/// rectangular grid): hinges along the grid's lines with the rigidities
/// [`rigidity_along_lines`] gives them. `None` for a mesh that is not a grid.
pub fn grid_line_hinges(mesh: &Mesh, rigidity: [f64; 2]) -> Option<Vec<Hinge>> {
    let [n1, _] = mesh.grid?;
    let yarns = mesh.yarns?;
    let x = &mesh.nodes;
    let lines = [unit(sub(x[1], x[0])), unit(sub(x[n1 + 1], x[0]))];
    let along = rigidity_along_lines(lines, yarns, rigidity);
    // The grid's lines at the angle between them (the rectangular blank's: 90°).
    let sine = norm(cross(lines[0], lines[1]));
    Some(line_hinges(mesh, mesh.grid?, along, sine))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_along_the_yarns_keep_their_rigidities_and_a_bend_between_loses_its_cross_terms() {
        let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert_eq!(rigidity_along_lines([x, y], [x, y], [0.3, 0.7]), [0.3, 0.7]);
        // Yarns at ±45° to the lines, B each: each line carries 2 B (1/√2)⁴ = B/2.
        let s = 0.5f64.sqrt();
        let along = rigidity_along_lines([x, y], [[s, s, 0.0], [s, -s, 0.0]], [1.0, 1.0]);
        assert!((along[0] - 0.5).abs() < 1e-12 && (along[1] - 0.5).abs() < 1e-12);
        // A weft at 80°: the warp line keeps B1 and a sliver of B2, the weft line sin⁴ 80°.
        let c = 80f64.to_radians();
        let along = rigidity_along_lines([x, y], [x, [c.cos(), c.sin(), 0.0]], [1.0, 1.0]);
        assert!((along[0] - (1.0 + c.cos().powi(4))).abs() < 1e-12);
        assert!((along[1] - c.sin().powi(4)).abs() < 1e-12);
    }

    #[test]
    fn a_weft_off_the_grid_gets_hinges_along_the_grid_lines() {
        let mut mesh =
            Mesh::yarn_grid([0.0, 0.0], [10.0, 8.0], [5, 4], std::f64::consts::FRAC_PI_2);
        let straight = yarn_hinges(&mesh, [1.0, 1.0]).unwrap();
        let c = 80f64.to_radians();
        mesh.yarns = Some([[1.0, 0.0, 0.0], [c.cos(), c.sin(), 0.0]]);
        assert!(yarn_hinges(&mesh, [1.0, 1.0]).is_none());
        let off = grid_line_hinges(&mesh, [1.0, 1.0]).unwrap();
        assert_eq!(off.len(), straight.len());
        // Warp lines first (j fixed: 5 × 4 interior nodes), then the weft lines.
        let warp = 5 * 4;
        assert!((off[0].k / straight[0].k - (1.0 + c.cos().powi(4))).abs() < 1e-12);
        assert!((off[warp].k / straight[warp].k - c.sin().powi(4)).abs() < 1e-12);
    }
}
