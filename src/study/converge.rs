//! The convergence study of `wovenform converge`: a scene solved on a ladder of mesh sizes and
//! on a ladder of load-step counts; a reference from Richardson extrapolation of the three
//! finest rungs (or the finest rung where the three are not monotone); each rung's error
//! against it, next to its run time.

use crate::core::drawing::{self, DrawingProblem};
use crate::scene::Scene;

/// The figures compared along a ladder.
pub const FIGURES: [&str; 4] = [
    "max_shear_deg",
    "punch_force_n",
    "draw_in_mm",
    "max_tension_n",
];

/// One solve of the ladder.
#[derive(Clone, Debug, PartialEq)]
pub struct Rung {
    /// `mesh` or `steps`.
    pub ladder: &'static str,
    pub element_size_mm: f64,
    /// The largest load increment allowed (1 / the least number of steps).
    pub max_step: f64,
    pub dofs: usize,
    pub steps: u32,
    pub newton_iterations: u32,
    pub wall_s: f64,
    pub converged: bool,
    /// `FIGURES`, in order.
    pub figures: [f64; 4],
}

/// The reference of a ladder, per figure: the value and how it was had.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    pub value: f64,
    /// The observed order of convergence (Richardson), if the three finest rungs gave one.
    pub order: Option<f64>,
}

/// A ladder and its reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Ladder {
    pub rungs: Vec<Rung>,
    pub reference: Vec<Reference>,
}

/// The limit and order of `f(h) = f0 + C h^p` through three points (h decreasing), when the
/// differences have one sign and an order in [0.2, 8] fits them.
pub fn richardson(h: [f64; 3], f: [f64; 3]) -> Option<(f64, f64)> {
    let (d1, d2) = (f[0] - f[1], f[1] - f[2]);
    if d1 * d2 <= 0.0 || d2.abs() < 1e-300 {
        return None;
    }
    let target = d1 / d2;
    let ratio = |p: f64| (h[0].powf(p) - h[1].powf(p)) / (h[1].powf(p) - h[2].powf(p));
    // The ratio grows with p (h decreasing): bisect.
    let (mut lo, mut hi) = (0.2, 8.0);
    if !(ratio(lo) <= target && target <= ratio(hi)) {
        return None;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if ratio(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let p = 0.5 * (lo + hi);
    let c = d2 / (h[1].powf(p) - h[2].powf(p));
    Some((f[2] - c * h[2].powf(p), p))
}

fn solve_rung(problem: &DrawingProblem, ladder: &'static str) -> Rung {
    let start = std::time::Instant::now();
    let r = drawing::solve(problem, &mut |_| {});
    let wall_s = start.elapsed().as_secs_f64();
    let max_shear = r.shear_deg.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    let max_tension = r.tension_max_n.iter().fold(0.0_f64, |m, t| m.max(*t));
    Rung {
        ladder,
        element_size_mm: problem.element_size,
        max_step: problem.solver.max_step,
        dofs: r.dofs,
        steps: r.stats.steps,
        newton_iterations: r.stats.newton_iterations,
        wall_s,
        converged: r.converged,
        figures: [max_shear, r.punch_force_n, r.draw_in_mm, max_tension],
    }
}

fn reference(rungs: &[Rung], size: impl Fn(&Rung) -> f64) -> Vec<Reference> {
    let ok: Vec<&Rung> = rungs.iter().filter(|r| r.converged).collect();
    (0..FIGURES.len())
        .map(|k| {
            let Some(finest) = ok.last() else {
                return Reference {
                    value: f64::NAN,
                    order: None,
                };
            };
            if ok.len() >= 3 {
                let t = &ok[ok.len() - 3..];
                if let Some((value, order)) = richardson(
                    [size(t[0]), size(t[1]), size(t[2])],
                    [t[0].figures[k], t[1].figures[k], t[2].figures[k]],
                ) {
                    return Reference {
                        value,
                        order: Some(order),
                    };
                }
            }
            Reference {
                value: finest.figures[k],
                order: None,
            }
        })
        .collect()
}

/// Solves `scene` (one thread) with each element size (coarse to fine); `progress` hears of each
/// rung as it ends.
pub fn mesh_ladder(scene: &Scene, sizes_mm: &[f64], progress: &mut dyn FnMut(&Rung)) -> Ladder {
    let rungs: Vec<Rung> = sizes_mm
        .iter()
        .map(|&h| {
            let mut p = scene.to_problem();
            p.solver.parallel = false;
            p.element_size = h;
            let r = solve_rung(&p, "mesh");
            progress(&r);
            r
        })
        .collect();
    let reference = reference(&rungs, |r| r.element_size_mm);
    Ladder { rungs, reference }
}

/// Solves `scene` (one thread, its own mesh) with at least each number of load steps (few to
/// many): the load increment is held at 1/N from the start.
pub fn step_ladder(scene: &Scene, counts: &[u32], progress: &mut dyn FnMut(&Rung)) -> Ladder {
    let rungs: Vec<Rung> = counts
        .iter()
        .map(|&n| {
            let mut p = scene.to_problem();
            p.solver.parallel = false;
            p.solver.max_step = 1.0 / n as f64;
            p.solver.initial_step = p.solver.max_step;
            let r = solve_rung(&p, "steps");
            progress(&r);
            r
        })
        .collect();
    let reference = reference(&rungs, |r| r.max_step);
    Ladder { rungs, reference }
}

impl Ladder {
    /// The error of rung `i` in figure `k`: degrees and millimetres as differences, forces and
    /// tensions in % of the reference.
    pub fn error(&self, i: usize, k: usize) -> f64 {
        let (v, r) = (self.rungs[i].figures[k], self.reference[k].value);
        if FIGURES[k].ends_with("_n") {
            100.0 * (v - r).abs() / r.abs().max(1e-12)
        } else {
            (v - r).abs()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn richardson_recovers_a_known_limit_and_order() {
        let f = |h: f64| 3.0 + 0.7 * h.powf(1.7);
        let h = [4.0, 2.5, 1.3];
        let (limit, order) = richardson(h, h.map(f)).unwrap();
        assert!((limit - 3.0).abs() < 1e-9, "{limit}");
        assert!((order - 1.7).abs() < 1e-9, "{order}");
        // Not monotone: no extrapolation.
        assert!(richardson(h, [1.0, 2.0, 1.5]).is_none());
    }
}
