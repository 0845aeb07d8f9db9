//! The blank mesh: 4-node elements laid along the yarns.

/// Nodes (initial positions, mm), quadrilaterals (counter-clockwise node indices) and the unit
/// warp and weft directions of the fabric: uniform over an initially flat blank, or `None` for
/// yarns along each element's natural directions (the paper's element; any initial shape).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub nodes: Vec<[f64; 3]>,
    pub quads: Vec<[usize; 4]>,
    pub yarns: Option<[[f64; 3]; 2]>,
    /// Grid size `[n1, n2]` (elements along warp and weft) when the mesh is a yarn grid.
    pub grid: Option<[usize; 2]>,
}

impl Mesh {
    /// A flat blank in the plane z = 0 meshed along the yarns: `n[α]` elements over `length[α]`
    /// (mm) along yarn α, the weft at `yarn_angle` (rad) from the warp, the warp along x, the
    /// first node at `origin`.
    pub fn yarn_grid(origin: [f64; 2], length: [f64; 2], n: [usize; 2], yarn_angle: f64) -> Mesh {
        let h1 = [1.0, 0.0, 0.0];
        let h2 = [yarn_angle.cos(), yarn_angle.sin(), 0.0];
        let mut nodes = Vec::with_capacity((n[0] + 1) * (n[1] + 1));
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let a = length[0] * i as f64 / n[0] as f64;
                let b = length[1] * j as f64 / n[1] as f64;
                nodes.push([
                    origin[0] + a * h1[0] + b * h2[0],
                    origin[1] + a * h1[1] + b * h2[1],
                    0.0,
                ]);
            }
        }
        let id = |i: usize, j: usize| j * (n[0] + 1) + i;
        let mut quads = Vec::with_capacity(n[0] * n[1]);
        for j in 0..n[1] {
            for i in 0..n[0] {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        Mesh {
            nodes,
            quads,
            yarns: Some([h1, h2]),
            grid: Some(n),
        }
    }

    pub fn dofs(&self) -> usize {
        3 * self.nodes.len()
    }
}

/// Each node's share of the initial area (a quarter of each of its elements), mm².
pub fn tributary_areas(mesh: &Mesh) -> Vec<f64> {
    let mut area = vec![0.0; mesh.nodes.len()];
    for q in &mesh.quads {
        let p = q.map(|n| mesh.nodes[n]);
        let a = 0.5
            * ((p[2][0] - p[0][0]) * (p[3][1] - p[1][1])
                - (p[3][0] - p[1][0]) * (p[2][1] - p[0][1]))
                .abs();
        for &n in q {
            area[n] += 0.25 * a;
        }
    }
    area
}
