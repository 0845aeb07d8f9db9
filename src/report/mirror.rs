//! The full blank from a solved quarter: mirror images about x = 0 and y = 0.
//!
//! A quarter model (x ≥ 0, y ≥ 0) stands for four copies of itself: as solved, mirrored about
//! x = 0, about y = 0, and about both. Pictures and VTU files show the whole blank so that a
//! reader sees the part that comes out of the press.

/// The mirror signs `(sx, sy)` of the four copies, the solved quarter first.
pub const COPIES: [[f64; 2]; 4] = [[1.0, 1.0], [-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]];

/// A plan quad: four corners `(x, y)`, mm.
pub type PlanQuad = [[f64; 2]; 4];

/// The four mirror images of a quarter's plan quads, with each quad's value copied: the solved
/// quarter first, then the images about x = 0, y = 0 and both (`4 × quads.len()` in all).
/// Mirrored quads keep their corner order (a fill does not care about orientation).
pub fn mirror_quads(quads: &[PlanQuad], values: &[f64]) -> (Vec<PlanQuad>, Vec<f64>) {
    assert_eq!(quads.len(), values.len(), "one value per quad");
    let mut out_quads = Vec::with_capacity(4 * quads.len());
    let mut out_values = Vec::with_capacity(4 * values.len());
    for [sx, sy] in COPIES {
        for (q, &v) in quads.iter().zip(values) {
            out_quads.push(q.map(|[x, y]| [sx * x, sy * y]));
            out_values.push(v);
        }
    }
    (out_quads, out_values)
}

/// The full mesh of a mirrored quarter, as indices into the quarter's nodes and elements.
/// Nodes on a symmetry plane are shared by the copies on either side of it.
#[derive(Clone, Debug, PartialEq)]
pub struct MirroredMesh {
    /// For each full-mesh node: the quarter's node and the mirror signs `[sx, sy]`.
    pub nodes: Vec<(usize, [f64; 2])>,
    /// Full-mesh quads (indices into `nodes`), counter-clockwise in plan like the quarter's.
    pub quads: Vec<[usize; 4]>,
    /// For each full-mesh quad: the quarter's element and the mirror signs.
    pub elements: Vec<(usize, [f64; 2])>,
}

impl MirroredMesh {
    /// Mirrors a quarter mesh given by its initial (flat) nodes: a node with `|x| ≤ tol` lies
    /// on the plane x = 0 and is not duplicated by the x-mirror (the same for y).
    pub fn of_quarter(initial: &[[f64; 3]], quads: &[[usize; 4]]) -> MirroredMesh {
        let extent = initial
            .iter()
            .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
        let tol = 1e-9 * extent.max(1.0);
        let mut nodes = Vec::new();
        // index[c][i]: the full node of quarter node i in copy c.
        let mut index = vec![vec![usize::MAX; initial.len()]; 4];
        for (c, [sx, sy]) in COPIES.into_iter().enumerate() {
            for (i, p) in initial.iter().enumerate() {
                // A node on a plane that this copy mirrors across is the one of the copy
                // without that mirror.
                let on_x = p[0].abs() <= tol;
                let on_y = p[1].abs() <= tol;
                let source = match (sx < 0.0 && on_x, sy < 0.0 && on_y) {
                    (false, false) => None,
                    (true, false) => Some(c - 1), // copies 1 → 0, 3 → 2
                    (false, true) => Some(c - 2), // copies 2 → 0, 3 → 1
                    (true, true) => Some(0),      // copy 3, the origin
                };
                index[c][i] = match source {
                    Some(s) => index[s][i],
                    None => {
                        nodes.push((i, [sx, sy]));
                        nodes.len() - 1
                    }
                };
            }
        }
        let mut full_quads = Vec::with_capacity(4 * quads.len());
        let mut elements = Vec::with_capacity(4 * quads.len());
        for (c, [sx, sy]) in COPIES.into_iter().enumerate() {
            let flips = sx * sy < 0.0;
            for (e, q) in quads.iter().enumerate() {
                let mut f = q.map(|n| index[c][n]);
                if flips {
                    // One reflection turns the quad over: reverse it to keep the orientation.
                    f = [f[0], f[3], f[2], f[1]];
                }
                full_quads.push(f);
                elements.push((e, [sx, sy]));
            }
        }
        MirroredMesh {
            nodes,
            quads: full_quads,
            elements,
        }
    }

    /// The identity: the solved mesh is already the full blank.
    pub fn identity(node_count: usize, quads: &[[usize; 4]]) -> MirroredMesh {
        MirroredMesh {
            nodes: (0..node_count).map(|i| (i, [1.0, 1.0])).collect(),
            quads: quads.to_vec(),
            elements: (0..quads.len()).map(|e| (e, [1.0, 1.0])).collect(),
        }
    }

    /// A point of the quarter carried to full-mesh node `n`.
    pub fn point(&self, n: usize, quarter_points: &[[f64; 3]]) -> [f64; 3] {
        let (i, [sx, sy]) = self.nodes[n];
        let p = quarter_points[i];
        [sx * p[0], sy * p[1], p[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×1 quarter: two unit squares along x starting at the origin, values 1 and 2.
    fn quarter() -> (Vec<PlanQuad>, Vec<f64>) {
        let q = |x0: f64| [[x0, 0.0], [x0 + 1.0, 0.0], [x0 + 1.0, 1.0], [x0, 1.0]];
        (vec![q(0.0), q(1.0)], vec![1.0, 2.0])
    }

    fn centre(q: &PlanQuad) -> [f64; 2] {
        let s = q.iter().fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
        [0.25 * s[0], 0.25 * s[1]]
    }

    #[test]
    fn a_quarter_maps_to_four_symmetric_copies() {
        let (quads, values) = quarter();
        let (full, v) = mirror_quads(&quads, &values);
        assert_eq!(full.len(), 4 * quads.len());
        assert_eq!(v.len(), full.len());
        // Every quad has its images about both axes, with the same value.
        for (q, &value) in full.iter().zip(&v) {
            let c = centre(q);
            for [sx, sy] in COPIES {
                let want = [sx * c[0], sy * c[1]];
                let found = full.iter().zip(&v).any(|(p, &w)| {
                    let d = centre(p);
                    (d[0] - want[0]).abs() < 1e-12 && (d[1] - want[1]).abs() < 1e-12 && w == value
                });
                assert!(found, "no image of {c:?} at {want:?}");
            }
        }
        // The copies cover [-2, 2] × [-1, 1]: total area 8, values summing to 4 × 3.
        let area: f64 = full
            .iter()
            .map(|q| {
                let mut a = 0.0;
                for i in 0..4 {
                    let (p, n) = (q[i], q[(i + 1) % 4]);
                    a += p[0] * n[1] - n[0] * p[1];
                }
                0.5 * f64::abs(a)
            })
            .sum();
        assert!((area - 8.0).abs() < 1e-12);
        assert_eq!(v.iter().sum::<f64>(), 12.0);
        let xs: Vec<f64> = full.iter().flatten().map(|p| p[0]).collect();
        let lo = xs.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!((lo, hi), (-2.0, 2.0));
    }

    #[test]
    fn the_mirrored_mesh_shares_the_nodes_on_the_planes() {
        // A 2×2 grid of unit squares on [0, 2]²: 9 nodes, 3 on x = 0, 3 on y = 0, 1 at both.
        let mut nodes = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                nodes.push([i as f64, j as f64, 0.0]);
            }
        }
        let quads: Vec<[usize; 4]> = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .map(|&(i, j)| {
                let n = |i: usize, j: usize| 3 * j + i;
                [n(i, j), n(i + 1, j), n(i + 1, j + 1), n(i, j + 1)]
            })
            .collect();
        let m = MirroredMesh::of_quarter(&nodes, &quads);
        // The full 4×4 grid on [-2, 2]² has 25 nodes and 16 quads.
        assert_eq!(m.nodes.len(), 25);
        assert_eq!(m.quads.len(), 16);
        let pts: Vec<[f64; 3]> = (0..m.nodes.len()).map(|n| m.point(n, &nodes)).collect();
        for a in 0..pts.len() {
            for b in a + 1..pts.len() {
                assert_ne!(pts[a], pts[b], "nodes {a} and {b} coincide");
            }
        }
        // Every quad stays counter-clockwise in plan (positive signed area) and unit.
        for q in &m.quads {
            let mut a = 0.0;
            for i in 0..4 {
                let (p, n) = (pts[q[i]], pts[q[(i + 1) % 4]]);
                a += p[0] * n[1] - n[0] * p[1];
            }
            assert!((0.5 * a - 1.0).abs() < 1e-12, "signed area {}", 0.5 * a);
        }
    }
}
