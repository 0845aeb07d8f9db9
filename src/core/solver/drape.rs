//! The drape predictor: a step with no secant to start from (the first, or the retry after a
//! cut) starts with each node a tool touched at the step's start moved with that tool, and the
//! fabric no tool touched draped between them: each coordinate's move harmonic over the mesh's
//! edges, as a membrane under even tension would hang, then put back onto any tool it entered,
//! and draped again with those nodes held, until no tool is entered.
//!
//! Without it the first step's projection put the nodes under the punch's nose on the nose
//! along its normal (moved outward by a tenth of a millimetre, a 4 % strain over one element)
//! and left their free neighbours where they were, so that one element's yarns carried the
//! punch's travel: the first residual was 1.1–1.5·10⁴ N and the first step took 11–15 iterations on the
//! paper's grid at standard.

use super::Solver;
use super::terms::NodalTerms;

/// The conjugate gradients stop when the Laplacian's residual is this share of the largest
/// move the tools set (a predictor needs no more).
const DRAPE_TOLERANCE: f64 = 1e-6;

/// At most this many drapes, each holding the nodes the last one's projection moved.
const DRAPE_PASSES: usize = 4;

impl Solver<'_> {
    /// Moves the model's free nodes to the drape predictor at load `lambda`. Terms that touch
    /// nothing (`carried_at_start` empty) get the plain projection.
    pub(super) fn drape(&mut self, lambda: f64, terms: &dyn NodalTerms) {
        let carried = terms.carried_at_start(lambda);
        if carried.is_empty() {
            self.project_onto_tools(lambda, terms);
            return;
        }
        let keep_slide = self.options.keep_slide;
        let x0 = self.model.positions();
        let mut x = x0.clone();
        for (xi, c) in x.iter_mut().zip(&carried) {
            xi[2] += c.unwrap_or(0.0);
        }
        let neighbours = edge_neighbours(&self.model.mesh.quads, x.len());
        let mut held: Vec<bool> = carried.iter().map(Option::is_some).collect();
        for _ in 0..DRAPE_PASSES {
            for m in 0..3 {
                let free: Vec<bool> = (0..x.len())
                    .map(|i| !held[i] && self.model.eq[3 * i + m] != usize::MAX)
                    .collect();
                let moved: Vec<f64> = (0..x.len()).map(|i| x[i][m] - x0[i][m]).collect();
                let draped = harmonic(&neighbours, &free, &moved);
                for (i, v) in draped.into_iter().enumerate() {
                    if free[i] {
                        x[i][m] = x0[i][m] + v;
                    }
                }
            }
            let draped = x.clone();
            terms.project(lambda, &mut x, keep_slide);
            let mut entered = false;
            for (h, (a, b)) in held.iter_mut().zip(x.iter().zip(&draped)) {
                if a != b && !*h {
                    *h = true;
                    entered = true;
                }
            }
            if !entered {
                break;
            }
        }
        self.model.set_free_positions(&x);
    }
}

/// Each node's neighbours along the quads' edges, without repeats.
fn edge_neighbours(quads: &[[usize; 4]], nodes: usize) -> Vec<Vec<usize>> {
    let mut neighbours = vec![Vec::new(); nodes];
    for q in quads {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            if !neighbours[a].contains(&b) {
                neighbours[a].push(b);
                neighbours[b].push(a);
            }
        }
    }
    neighbours
}

/// The moves of the `free` nodes that make each free node's move the mean of its neighbours',
/// the others held at `moved`: conjugate gradients on the graph Laplacian, symmetric and
/// positive definite on a free set of which every part reaches a held node (a part that
/// reaches none keeps a zero move). Returns every node's move.
fn harmonic(neighbours: &[Vec<usize>], free: &[bool], moved: &[f64]) -> Vec<f64> {
    let n = moved.len();
    let scale = moved.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut v: Vec<f64> = (0..n)
        .map(|i| if free[i] { 0.0 } else { moved[i] })
        .collect();
    if scale == 0.0 {
        return v;
    }
    // The Laplacian's rows at the free nodes; the held nodes' entries of `w` enter as they are.
    let laplacian = |w: &[f64], out: &mut [f64]| {
        for i in 0..n {
            out[i] = if free[i] {
                let sum: f64 = neighbours[i].iter().map(|&j| w[j]).sum();
                neighbours[i].len() as f64 * w[i] - sum
            } else {
                0.0
            };
        }
    };
    let absolute = DRAPE_TOLERANCE * scale;
    crate::core::sparse::conjugate::relax_free(laplacian, &mut v, 0.0, absolute, n);
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a chain held at both ends, the harmonic move is the straight line between them.
    #[test]
    fn a_chain_is_draped_straight() {
        let n: usize = 11;
        let neighbours: Vec<Vec<usize>> = (0..n)
            .map(|i| {
                [i.checked_sub(1), (i + 1 < n).then_some(i + 1)]
                    .into_iter()
                    .flatten()
                    .collect()
            })
            .collect();
        let free: Vec<bool> = (0..n).map(|i| i != 0 && i != n - 1).collect();
        let mut moved = vec![0.0; n];
        moved[0] = -1.4;
        let v = harmonic(&neighbours, &free, &moved);
        for (i, vi) in v.iter().enumerate() {
            let line: f64 = -1.4 * (1.0 - i as f64 / (n - 1) as f64);
            assert!((*vi - line).abs() < 1e-9, "node {i}: {vi} against {line}");
        }
    }

    /// On a grid of quads held on its border at a linear function's values, the harmonic move
    /// inside is that function (a linear function is discretely harmonic on a regular grid).
    #[test]
    fn a_grid_held_at_a_plane_is_draped_flat() {
        let (nx, ny) = (9, 7);
        let id = |i: usize, j: usize| j * nx + i;
        let quads: Vec<[usize; 4]> = (0..ny - 1)
            .flat_map(|j| (0..nx - 1).map(move |i| (i, j)))
            .map(|(i, j)| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
            .collect();
        let neighbours = edge_neighbours(&quads, nx * ny);
        let plane = |k: usize| 0.3 * (k % nx) as f64 - 0.7 * (k / nx) as f64 + 2.0;
        let border = |k: usize| {
            let (i, j) = (k % nx, k / nx);
            i == 0 || i == nx - 1 || j == 0 || j == ny - 1
        };
        let free: Vec<bool> = (0..nx * ny).map(|k| !border(k)).collect();
        let moved: Vec<f64> = (0..nx * ny)
            .map(|k| if border(k) { plane(k) } else { 0.0 })
            .collect();
        let v = harmonic(&neighbours, &free, &moved);
        for (k, vk) in v.iter().enumerate() {
            assert!(
                (vk - plane(k)).abs() < 1e-5,
                "node {k}: {vk} against {}",
                plane(k)
            );
        }
    }
}
