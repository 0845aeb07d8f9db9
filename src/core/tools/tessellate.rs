//! A closed triangle surface from a signed field by surface nets (dual contouring without the
//! quadric): the field is sampled on a regular grid; each grid cell whose corners change sign
//! gets one vertex, at the mean of its edges' crossings moved onto the zero level set by a few
//! Newton steps; each grid edge whose ends change sign gets a quad joining the vertices of the
//! four cells around it, split into two triangles along its shorter diagonal.
//!
//! Convention: the field is negative inside the material and positive outside (a signed
//! distance, or any field with the same zero set and no vanishing gradient there). The
//! triangles wind counter-clockwise seen from where the field is positive, so their normals
//! point out of the material, as [`TriSurface::check`] wants.
//!
//! The result is the same on any number of threads: every sample and every vertex is computed
//! on its own and the output is put together in grid order.

use rayon::prelude::*;

use super::surface::TriSurface;

/// Newton steps at most when moving a vertex onto the zero level set.
const NEWTON_STEPS: usize = 8;

/// The field of `tool` cut by a box: the material of both (the larger of the two fields).
/// With `d_box` from [`box_field`], it is positive on and beyond the box's faces, which closes
/// an unbounded tool (a punch extruded upward, a die's infinite plate).
pub fn capped(d_tool: f64, d_box: f64) -> f64 {
    d_tool.max(d_box)
}

/// A field of the box `[lo, hi]`: negative inside, zero on its faces (the exact distance
/// inside and on the faces; outside it is the largest distance to one face's plane).
pub fn box_field(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    (0..3)
        .map(|i| (lo[i] - p[i]).max(p[i] - hi[i]))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The regular grid over a box: `n[i]` cells of size `h[i]` along each axis, nodes
/// `lo + k·h`.
#[derive(Clone, Copy, Debug)]
struct Grid {
    lo: [f64; 3],
    h: [f64; 3],
    n: [usize; 3],
}

impl Grid {
    /// The grid over `[lo, hi]` whose cells are at most `spacing` (exactly `spacing` when the
    /// box's sides are whole multiples of it).
    fn new(lo: [f64; 3], hi: [f64; 3], spacing: f64) -> Grid {
        let mut n = [1; 3];
        let mut h = [0.0; 3];
        for i in 0..3 {
            let cells = ((hi[i] - lo[i]) / spacing - 1e-9).ceil();
            n[i] = if cells.is_finite() {
                (cells as usize).max(1)
            } else {
                1
            };
            h[i] = (hi[i] - lo[i]) / n[i] as f64;
        }
        Grid { lo, h, n }
    }

    fn nodes(&self) -> [usize; 3] {
        [self.n[0] + 1, self.n[1] + 1, self.n[2] + 1]
    }

    fn node_index(&self, i: [usize; 3]) -> usize {
        let m = self.nodes();
        (i[2] * m[1] + i[1]) * m[0] + i[0]
    }

    fn cell_index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }

    fn node(&self, i: [usize; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| self.lo[a] + i[a] as f64 * self.h[a])
    }

    fn on_boundary(&self, i: [usize; 3]) -> bool {
        (0..3).any(|a| i[a] == 0 || i[a] == self.n[a])
    }
}

/// The closed surface `field = 0` inside the box `[lo, hi]` by surface nets on a grid of
/// cells of at most `spacing_mm` (exactly `spacing_mm` when the box's sides are whole
/// multiples of it; grid nodes at `lo + k·spacing`).
///
/// The field must be positive on the box's faces (cap it with [`capped`] and [`box_field`]
/// over a slightly smaller box) so that the surface is closed; the grid's outermost nodes are
/// taken as outside whatever the field says there, so the result is always closed, but where
/// the field is not positive on the faces the box cuts the surface and the vertices there are
/// off the zero set.
///
/// Each vertex is moved from the mean of its cell's edge crossings onto the zero set by Newton
/// steps `p -= f ∇f/|∇f|²` (gradient by central differences), as long as it stays within its
/// cell grown by half a cell on each side; otherwise it keeps the mean point. On a smooth part
/// of the surface every vertex lies on it to rounding; on a sharp edge (where a box caps a tool)
/// the vertices lie on one of the faces and the edge itself is cut by a chamfer of about one
/// cell. Features thinner than a cell are lost; where one is about a cell thick, a grid face
/// whose diagonal corners alone are inside would give an edge of four triangles, which
/// [`TriSurface::check`] refuses (a finer spacing resolves it).
pub fn tessellate(
    field: &(dyn Fn([f64; 3]) -> f64 + Sync),
    lo: [f64; 3],
    hi: [f64; 3],
    spacing_mm: f64,
) -> TriSurface {
    let grid = Grid::new(lo, hi, spacing_mm);
    let values = sample(field, &grid);
    let (cells, vertices) = cell_vertices(field, &grid, &values);
    let mut vertex_of = vec![u32::MAX; grid.n.iter().product()];
    for (id, &c) in cells.iter().enumerate() {
        vertex_of[c] = id as u32;
    }
    let slabs = grid.nodes()[2];
    let triangles: Vec<[u32; 3]> = (0..slabs)
        .into_par_iter()
        .map(|k| slab_triangles(&grid, &values, &vertex_of, &vertices, k))
        .collect::<Vec<_>>()
        .concat();
    TriSurface {
        vertices,
        triangles,
    }
}

/// The field at every grid node (the outermost nodes never negative), one z slab per task.
fn sample(field: &(dyn Fn([f64; 3]) -> f64 + Sync), grid: &Grid) -> Vec<f64> {
    let m = grid.nodes();
    let mut values = vec![0.0; m[0] * m[1] * m[2]];
    values
        .par_chunks_mut(m[0] * m[1])
        .enumerate()
        .for_each(|(k, slab)| {
            for j in 0..m[1] {
                for i in 0..m[0] {
                    let node = [i, j, k];
                    let v = field(grid.node(node));
                    slab[j * m[0] + i] = if grid.on_boundary(node) {
                        v.max(0.0)
                    } else {
                        v
                    };
                }
            }
        });
    values
}

fn inside(v: f64) -> bool {
    v < 0.0
}

/// The cells that the surface crosses (their indices, in grid order) and their vertices.
fn cell_vertices(
    field: &(dyn Fn([f64; 3]) -> f64 + Sync),
    grid: &Grid,
    values: &[f64],
) -> (Vec<usize>, Vec<[f64; 3]>) {
    let per_slab: Vec<Vec<(usize, [f64; 3])>> = (0..grid.n[2])
        .into_par_iter()
        .map(|k| {
            let mut found = Vec::new();
            for j in 0..grid.n[1] {
                for i in 0..grid.n[0] {
                    if let Some(v) = cell_vertex(field, grid, values, [i, j, k]) {
                        found.push((grid.cell_index([i, j, k]), v));
                    }
                }
            }
            found
        })
        .collect();
    per_slab.into_iter().flatten().unzip()
}

/// The vertex of cell `c`, if the surface crosses it.
fn cell_vertex(
    field: &(dyn Fn([f64; 3]) -> f64 + Sync),
    grid: &Grid,
    values: &[f64],
    c: [usize; 3],
) -> Option<[f64; 3]> {
    // Corner b (bits x, y, z) is node c + (b & 1, b >> 1 & 1, b >> 2 & 1).
    let offset = |b: usize| [c[0] + (b & 1), c[1] + ((b >> 1) & 1), c[2] + ((b >> 2) & 1)];
    let f: [f64; 8] = std::array::from_fn(|b| values[grid.node_index(offset(b))]);
    let inner = f.iter().filter(|v| inside(**v)).count();
    if inner == 0 || inner == 8 {
        return None;
    }
    let mut sum = [0.0; 3];
    let mut count = 0.0;
    for a in 0..8 {
        for axis in 0..3 {
            let b = a | (1 << axis);
            if b == a || inside(f[a]) == inside(f[b]) {
                continue;
            }
            let t = f[a] / (f[a] - f[b]);
            let (pa, pb) = (grid.node(offset(a)), grid.node(offset(b)));
            for i in 0..3 {
                sum[i] += pa[i] + t * (pb[i] - pa[i]);
            }
            count += 1.0;
        }
    }
    let mean = sum.map(|s| s / count);
    let corner = grid.node(c);
    let lo = [0, 1, 2].map(|i| corner[i] - 0.5 * grid.h[i]);
    let hi = [0, 1, 2].map(|i| corner[i] + 1.5 * grid.h[i]);
    Some(onto_surface(field, mean, lo, hi, grid.h))
}

/// `p` moved onto the zero set by Newton steps, or `p` itself when a step leaves `[lo, hi]`
/// or the steps do not come nearer the zero set.
fn onto_surface(
    field: &(dyn Fn([f64; 3]) -> f64 + Sync),
    p: [f64; 3],
    lo: [f64; 3],
    hi: [f64; 3],
    h: [f64; 3],
) -> [f64; 3] {
    let size = h[0].max(h[1]).max(h[2]);
    let (tol, step) = (1e-12 * size, 1e-5 * size);
    let f0 = field(p);
    let (mut q, mut fq) = (p, f0);
    for _ in 0..NEWTON_STEPS {
        if fq.abs() <= tol {
            break;
        }
        let g: [f64; 3] = std::array::from_fn(|i| {
            let (mut plus, mut minus) = (q, q);
            plus[i] += step;
            minus[i] -= step;
            (field(plus) - field(minus)) / (2.0 * step)
        });
        let g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        // No gradient (or not a number): no direction to move in.
        if g2.is_nan() || g2 <= 1e-20 {
            break;
        }
        let next = [0, 1, 2].map(|i| q[i] - fq * g[i] / g2);
        if (0..3).any(|i| !(next[i] >= lo[i] && next[i] <= hi[i])) {
            return p;
        }
        q = next;
        fq = field(q);
    }
    if fq.abs() <= f0.abs() { q } else { p }
}

/// The triangles of the sign-changing grid edges that start at nodes of z slab `k`.
fn slab_triangles(
    grid: &Grid,
    values: &[f64],
    vertex_of: &[u32],
    vertices: &[[f64; 3]],
    k: usize,
) -> Vec<[u32; 3]> {
    let m = grid.nodes();
    let mut out = Vec::new();
    for j in 0..m[1] {
        for i in 0..m[0] {
            let a = [i, j, k];
            for axis in 0..3 {
                if let Some(quad) = edge_quad(grid, values, vertex_of, a, axis) {
                    split(&quad, vertices, &mut out);
                }
            }
        }
    }
    out
}

/// The quad of the grid edge from node `a` along `axis`, if its ends change sign: the
/// vertices of the four cells around it, counter-clockwise seen from the outer end.
fn edge_quad(
    grid: &Grid,
    values: &[f64],
    vertex_of: &[u32],
    a: [usize; 3],
    axis: usize,
) -> Option<[u32; 4]> {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    // The four cells around the edge exist only off the grid's faces along u and v.
    if a[axis] >= grid.n[axis] || a[u] == 0 || a[v] == 0 || a[u] >= grid.n[u] || a[v] >= grid.n[v] {
        return None;
    }
    let mut b = a;
    b[axis] += 1;
    let (fa, fb) = (values[grid.node_index(a)], values[grid.node_index(b)]);
    if inside(fa) == inside(fb) {
        return None;
    }
    // Cells at (u, v) offsets (−1, −1), (0, −1), (0, 0), (−1, 0): counter-clockwise about +axis
    // (u × v = axis).
    let cell = |du: usize, dv: usize| {
        let mut c = a;
        c[u] -= du;
        c[v] -= dv;
        vertex_of[grid.cell_index(c)]
    };
    let quad = [cell(1, 1), cell(0, 1), cell(0, 0), cell(1, 0)];
    debug_assert!(quad.iter().all(|&q| q != u32::MAX));
    // Outward (towards positive field) is +axis when the edge leaves the material.
    Some(if inside(fa) {
        quad
    } else {
        [quad[0], quad[3], quad[2], quad[1]]
    })
}

/// Two triangles of `quad` along its shorter diagonal.
fn split(quad: &[u32; 4], vertices: &[[f64; 3]], out: &mut Vec<[u32; 3]>) {
    let dist2 = |a: u32, b: u32| {
        let (p, q) = (vertices[a as usize], vertices[b as usize]);
        (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f64>()
    };
    let [q0, q1, q2, q3] = *quad;
    if dist2(q0, q2) <= dist2(q1, q3) {
        out.push([q0, q1, q2]);
        out.push([q0, q2, q3]);
    } else {
        out.push([q0, q1, q3]);
        out.push([q1, q2, q3]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn norm(p: [f64; 3]) -> f64 {
        (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
    }

    fn sphere(r: f64) -> impl Fn([f64; 3]) -> f64 + Sync {
        move |p| norm(p) - r
    }

    /// Vertices, edges and triangles: V − E + F = 2 − 2·genus.
    fn euler_characteristic(s: &TriSurface) -> i64 {
        let edges = 3 * s.triangles.len() / 2;
        s.vertices.len() as i64 - edges as i64 + s.triangles.len() as i64
    }

    #[test]
    fn a_sphere_is_closed_outward_and_on_its_surface() {
        let s = tessellate(&sphere(10.0), [-12.0; 3], [12.0; 3], 1.0);
        let volume = s.check().unwrap();
        let exact = 4.0 / 3.0 * PI * 1000.0;
        assert!(
            (volume / exact - 1.0).abs() < 0.005,
            "volume {volume} against {exact}"
        );
        let worst = s
            .vertices
            .iter()
            .map(|v| (norm(*v) - 10.0).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "a vertex {worst} mm off the sphere");
        assert_eq!(euler_characteristic(&s), 2);
    }

    #[test]
    fn a_cube_with_rounded_edges_keeps_its_volume() {
        // Half side 8 of which the edges and corners are rounded with radius 2.
        let (b, r) = (6.0, 2.0);
        let field = move |p: [f64; 3]| {
            let q = p.map(|v| v.abs() - b);
            let out = norm(q.map(|v| v.max(0.0)));
            out + q[0].max(q[1]).max(q[2]).min(0.0) - r
        };
        let s = tessellate(&field, [-9.5; 3], [9.5; 3], 0.5);
        let volume = s.check().unwrap();
        let side = 2.0 * b;
        let exact = side.powi(3)
            + 6.0 * side * side * r
            + 3.0 * side * PI * r * r
            + 4.0 / 3.0 * PI * r.powi(3);
        assert!(
            (volume / exact - 1.0).abs() < 0.002,
            "volume {volume} against {exact}"
        );
        let worst = s
            .vertices
            .iter()
            .map(|v| field(*v).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "a vertex {worst} mm off the surface");
        assert_eq!(euler_characteristic(&s), 2);
    }

    #[test]
    fn a_slab_with_a_hole_has_genus_one() {
        // A die's topology: a plate 6 mm thick, 30 × 30 mm, with a hole of radius 5 mm.
        let field = |p: [f64; 3]| {
            let slab = capped(p[2].abs() - 3.0, box_field(p, [-15.0; 3], [15.0; 3]));
            capped(slab, 5.0 - (p[0] * p[0] + p[1] * p[1]).sqrt())
        };
        let s = tessellate(&field, [-16.5; 3], [16.5; 3], 1.0);
        let volume = s.check().unwrap();
        assert_eq!(euler_characteristic(&s), 0, "genus one");
        // The box's sharp edges are chamfered by about a cell: 1 % of the volume at most.
        let exact = (30.0 * 30.0 - PI * 25.0) * 6.0;
        assert!(
            (volume / exact - 1.0).abs() < 0.01,
            "volume {volume} against {exact}"
        );
        // The faces are planes: their vertices lie in them.
        let on_top = s
            .vertices
            .iter()
            .filter(|v| (v[2] - 3.0).abs() < 1e-9)
            .count();
        assert!(on_top > 500, "{on_top} vertices on the top face");
    }

    #[test]
    fn triangles_grow_as_the_inverse_square_of_the_spacing() {
        let count = |h: f64| {
            tessellate(&sphere(10.0), [-12.0; 3], [12.0; 3], h)
                .triangles
                .len()
        };
        let (coarse, fine) = (count(1.0), count(0.5));
        let ratio = fine as f64 / coarse as f64;
        assert!(
            (3.6..4.4).contains(&ratio),
            "{coarse} → {fine}: ratio {ratio}"
        );
    }

    #[test]
    fn a_field_open_at_the_box_is_closed_by_it() {
        // The half space z < 0.3 is not capped: the box's faces close it.
        let s = tessellate(&|p: [f64; 3]| p[2] - 0.3, [-4.0; 3], [4.0; 3], 1.0);
        let volume = s.check().unwrap();
        assert!(volume > 0.0);
    }

    #[test]
    fn the_result_does_not_depend_on_the_threads() {
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| tessellate(&sphere(7.3), [-9.0; 3], [9.0; 3], 0.7))
        };
        assert_eq!(run(1), run(3));
    }
}
