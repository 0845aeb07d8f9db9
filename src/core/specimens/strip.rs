//! What the bending checks' strips share (`core::specimens::cantilever`, `core::specimens::euler_strip`): the strip's
//! yarn grid with clamped rows, the hinges at a clamp's edge, the loads of its own weight or a
//! trigger, and the solver settings for forces of micronewtons against yarns of 10⁴ N.

use crate::core::fabric::bending::Hinge;
use crate::core::membrane::mesh::Mesh;
use crate::core::solver::{NodalSums, NodalTerms, NodeBlock, SolverOptions};

/// A strip of width `width` along x from `−h` to `length + extra·h` (`h` ≤ `element_size`, a
/// whole number of elements over `length`): the warp along it, at least `min_elements` over
/// its length. Returns the mesh and `h`.
pub fn strip_mesh(
    length: f64,
    width: f64,
    element_size: f64,
    min_elements: usize,
    extra: usize,
) -> (Mesh, f64) {
    let n = ((length / element_size).ceil() as usize).max(min_elements);
    let m = (width / element_size).round().max(1.0) as usize;
    let h = length / n as f64;
    let mesh = Mesh::yarn_grid(
        [-h, -0.5 * width],
        [length + (1 + extra) as f64 * h, width],
        [n + 1 + extra, m],
        std::f64::consts::FRAC_PI_2,
    );
    (mesh, h)
}

/// Doubles the stiffness of each hinge that turns the free strip against a clamped segment
/// (`column` gives a node's index along the strip, `clamped` whether that column is held): its
/// curvature acts over the half segment on the strip's side only, so it stands for h/2 of
/// length, not h (`k = B w / L̄`). Without this the root is too soft by h/2 (the cantilever's
/// tip falls 2h/L too far).
pub fn stiffen_clamp_edges(
    hinges: &mut [Hinge],
    column: impl Fn(usize) -> usize,
    clamped: impl Fn(usize) -> bool,
) {
    for h in hinges.iter_mut() {
        let [a, b, c] = h.nodes.map(&column);
        if clamped(b) && (clamped(a) != clamped(c)) {
            h.k *= 2.0;
        }
    }
}

/// The solver's settings for a strip loaded by its weight or a trigger: the tolerance relative
/// to the load at 1e-4 of it (the load is micronewtons per node; the yarns' round-off, C times a
/// strain of 1e-16, some 1e-11 N, sits near 1e-6 of it), no floor (a yarn strain's worth of
/// tension would call any state balanced), and no pseudo-transient damping (scaled by the
/// yarns' tensile stiffness, some 10⁵ times the strip's bending stiffness, it would freeze the
/// bending; a clamped strip is no mechanism).
pub fn strip_solver(options: &SolverOptions) -> SolverOptions {
    let mut options = options.clone();
    options.tol_floor = 0.0;
    options.tol_force = options.tol_force.max(1e-4);
    options.stabilisation = 0.0;
    options
}

/// A dead load along z on each node (N): times the load factor when `scaled` (a weight applied
/// in steps), or the same at every load factor (a trigger held while something else is loaded).
pub struct DeadLoad {
    pub force_z: Vec<f64>,
    pub scaled: bool,
}

impl NodalTerms for DeadLoad {
    fn add(
        &self,
        lambda: f64,
        x: &[[f64; 3]],
        r: &mut [f64],
        _: Option<&mut [NodeBlock]>,
    ) -> Option<NodalSums> {
        let factor = if self.scaled { lambda } else { 1.0 };
        let mut sums = NodalSums::default();
        for (i, (f, p)) in self.force_z.iter().zip(x).enumerate() {
            let f = factor * f;
            r[3 * i + 2] -= f;
            sums.energy -= f * p[2];
            sums.scale += f * f;
        }
        sums.energy_frozen = sums.energy;
        sums.scale = sums.scale.sqrt();
        Some(sums)
    }
}
