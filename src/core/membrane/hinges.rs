//! The bending hinges of a yarn-grid blank: one at each interior node of each warp and weft
//! line, with the stiffness its share of the fabric's rigidity gives (the law is
//! [`crate::core::fabric::bending`]'s).

use crate::core::fabric::bending::Hinge;
use crate::core::membrane::mesh::Mesh;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

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
    let len = |a: usize, b: usize| norm(sub(x[b], x[a]));
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
    let sine = mesh.yarns.map_or(1.0, |[h1, h2]| {
        let c = [
            h1[1] * h2[2] - h1[2] * h2[1],
            h1[2] * h2[0] - h1[0] * h2[2],
            h1[0] * h2[1] - h1[1] * h2[0],
        ];
        norm(c)
    });
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
    Some(hinges)
}
