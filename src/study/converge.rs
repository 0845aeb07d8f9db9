//! The convergence study of `wovenform converge`: a scene solved on a ladder of mesh sizes and
//! on a ladder of load-step counts (at least three rungs each, coarse to fine, all distinct);
//! a reference for each figure with its own uncertainty, and each rung's error against it,
//! next to its run time.
//!
//! The reference is the Richardson extrapolation of the three finest rungs that converged,
//! when they are monotone and an order in [0.2, 8] fits them; its uncertainty is the size of
//! the correction the extrapolation made (the distance from the finest rung to the limit).
//! Otherwise it is the finest rung, and its uncertainty the largest distance from it to the
//! two rungs before it. A rung's error is its distance to the reference plus the reference's
//! uncertainty: an error bound, never zero unless the rungs agree exactly.

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

/// The reference of a ladder, per figure: the value, how it was had, and how far it can be off.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    pub value: f64,
    /// The observed order of convergence (Richardson), if the three finest rungs gave one.
    pub order: Option<f64>,
    /// How far the reference itself can be off (the figure's unit): the extrapolation's last
    /// correction, or the spread of the finest rungs. NaN when fewer than two rungs converged.
    pub uncertainty: f64,
}

/// A ladder that cannot give a reference.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LadderError {
    #[error("{option} {shown}: expected at least three rungs, {order}, e.g. {option} {example}")]
    TooFew {
        option: &'static str,
        shown: String,
        order: &'static str,
        example: &'static str,
    },
    #[error(
        "{option} {shown}: expected {order} (each rung {each} than the one before, no repeats), e.g. {option} {example}"
    )]
    NotOrdered {
        option: &'static str,
        shown: String,
        order: &'static str,
        each: &'static str,
        example: &'static str,
    },
    #[error("{option} {shown}: expected {what}")]
    OutOfRange {
        option: &'static str,
        shown: String,
        what: String,
    },
    /// A rung of the mesh ladder breaks a bound of the scene (or this machine's memory).
    #[error("--sizes {size}: {detail}")]
    Rung { size: f64, detail: String },
}

/// The two ladders a convergence study climbs: element sizes coarse to fine, mm, and least
/// load-step counts few to many.
#[derive(Clone, Debug, PartialEq)]
pub struct Ladders {
    pub sizes_mm: Vec<f64>,
    pub steps: Vec<u32>,
}

impl Ladders {
    /// The ladders asked for, an empty one taking its default (the scene's element size times
    /// 2, √2, 1, 1/√2, 1/2; 4, 8, 16, 32, 64 steps), checked: each rung of the mesh ladder is
    /// the scene at that size, within the scene's bounds and this machine's memory, before any
    /// rung is solved.
    pub fn new(scene: &Scene, sizes_mm: &[f64], steps: &[u32]) -> Result<Ladders, LadderError> {
        let h = scene.mesh.element_size;
        let sizes_mm = if sizes_mm.is_empty() {
            [2.0, 2f64.sqrt(), 1.0, 0.5f64.sqrt(), 0.5]
                .iter()
                .map(|k| (h * k * 1000.0).round() / 1000.0)
                .collect()
        } else {
            sizes_mm.to_vec()
        };
        let steps = if steps.is_empty() {
            vec![4, 8, 16, 32, 64]
        } else {
            steps.to_vec()
        };
        check_sizes(&sizes_mm)?;
        for &size in &sizes_mm {
            let mut rung = scene.clone();
            rung.mesh.element_size = size;
            rung.validate("").map_err(|e| LadderError::Rung {
                size,
                detail: e.detail,
            })?;
        }
        check_steps(&steps)?;
        Ok(Ladders { sizes_mm, steps })
    }

    /// Solves in all.
    pub fn len(&self) -> usize {
        self.sizes_mm.len() + self.steps.len()
    }

    /// No rung (never, once checked).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn shown<T: ToString>(values: &[T]) -> String {
    values
        .iter()
        .map(T::to_string)
        .collect::<Vec<_>>()
        .join(",")
}

/// Checks a mesh ladder: three or more element sizes > 0 mm, strictly decreasing.
pub fn check_sizes(sizes_mm: &[f64]) -> Result<(), LadderError> {
    let (option, example) = ("--sizes", "5,3.5,2.5");
    let order = "element sizes coarse to fine";
    if sizes_mm.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(LadderError::OutOfRange {
            option,
            shown: shown(sizes_mm),
            what: "element sizes > 0 mm".into(),
        });
    }
    if sizes_mm.len() < 3 {
        return Err(LadderError::TooFew {
            option,
            shown: shown(sizes_mm),
            order,
            example,
        });
    }
    if sizes_mm.windows(2).any(|w| w[1] >= w[0]) {
        return Err(LadderError::NotOrdered {
            option,
            shown: shown(sizes_mm),
            order,
            each: "smaller",
            example,
        });
    }
    Ok(())
}

/// Checks a step ladder: three or more step counts ≥ 1, strictly increasing.
pub fn check_steps(counts: &[u32]) -> Result<(), LadderError> {
    let (option, example) = ("--steps", "4,8,16");
    let order = "step counts few to many";
    // More steps than the solver's budget could never reach the end of the stroke.
    let budget = crate::core::solver::SolverOptions::default().max_steps;
    if counts.iter().any(|&n| n == 0 || n > budget) {
        return Err(LadderError::OutOfRange {
            option,
            shown: shown(counts),
            what: format!("step counts from 1 to {budget} (the solver's budget of accepted steps)"),
        });
    }
    if counts.len() < 3 {
        return Err(LadderError::TooFew {
            option,
            shown: shown(counts),
            order,
            example,
        });
    }
    if counts.windows(2).any(|w| w[1] <= w[0]) {
        return Err(LadderError::NotOrdered {
            option,
            shown: shown(counts),
            order,
            each: "larger",
            example,
        });
    }
    Ok(())
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
    let max_shear = r.max_shear().1;
    let max_tension = r.max_tension_n();
    Rung {
        ladder,
        element_size_mm: problem.element_size_mm,
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
                    uncertainty: f64::NAN,
                };
            };
            let fine = finest.figures[k];
            let last3 = &ok[ok.len().saturating_sub(3)..];
            if let [a, b, c] = last3
                && let Some((value, order)) = richardson(
                    [size(a), size(b), size(c)],
                    [a.figures[k], b.figures[k], c.figures[k]],
                )
            {
                return Reference {
                    value,
                    order: Some(order),
                    uncertainty: (fine - value).abs(),
                };
            }
            // No extrapolation: the finest rung, no better known than the spread before it.
            let spread = last3[..last3.len() - 1]
                .iter()
                .map(|r| (r.figures[k] - fine).abs())
                .fold(f64::NAN, f64::max);
            Reference {
                value: fine,
                order: None,
                uncertainty: spread,
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
            p.element_size_mm = h;
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
    /// The error bound of rung `i` in figure `k`: its distance to the reference plus the
    /// reference's uncertainty; degrees and millimetres as differences, forces and tensions in
    /// % of the reference.
    pub fn error(&self, i: usize, k: usize) -> f64 {
        let v = self.rungs[i].figures[k];
        let Reference {
            value, uncertainty, ..
        } = self.reference[k];
        let bound = (v - value).abs() + uncertainty;
        if FIGURES[k].ends_with("_n") {
            100.0 * bound / value.abs().max(1e-12)
        } else {
            bound
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

    fn rung(h: f64, shear: f64) -> Rung {
        Rung {
            ladder: "mesh",
            element_size_mm: h,
            max_step: 0.5,
            dofs: 0,
            steps: 0,
            newton_iterations: 0,
            wall_s: 1.0,
            converged: true,
            figures: [shear, 1000.0, 1.0, 100.0],
        }
    }

    #[test]
    fn no_rung_is_its_own_error_free_reference() {
        // f(h) = 60 − 2 h^1.5 on h = 4, 2.5, 1.3: the limit 60; the finest rung's bound is
        // twice its distance to it (distance + the extrapolation's correction).
        let f = |h: f64| 60.0 - 2.0 * h.powf(1.5);
        let rungs: Vec<Rung> = [4.0, 2.5, 1.3].iter().map(|&h| rung(h, f(h))).collect();
        let refs = reference(&rungs, |r| r.element_size_mm);
        let ladder = Ladder {
            rungs,
            reference: refs,
        };
        assert!((ladder.reference[0].value - 60.0).abs() < 1e-9);
        let fine_distance = 2.0 * 1.3f64.powf(1.5);
        assert!((ladder.error(2, 0) - 2.0 * fine_distance).abs() < 1e-9);
        // Not monotone: the finest rung, with the spread of the rungs before it.
        let rungs = vec![rung(4.0, 58.0), rung(2.5, 61.0), rung(1.3, 60.0)];
        let refs = reference(&rungs, |r| r.element_size_mm);
        let ladder = Ladder {
            rungs,
            reference: refs,
        };
        assert_eq!(ladder.reference[0].value, 60.0);
        assert_eq!(ladder.reference[0].uncertainty, 2.0);
        assert_eq!(ladder.error(2, 0), 2.0);
        assert_eq!(ladder.error(0, 0), 4.0);
    }

    #[test]
    fn ladders_must_go_coarse_to_fine_with_three_distinct_rungs() {
        assert!(check_sizes(&[5.0, 3.5, 2.5]).is_ok());
        assert!(check_steps(&[4, 8, 16]).is_ok());
        for bad in [
            &[6.0, 10.0, 12.0][..],
            &[5.0, 5.0, 2.5],
            &[5.0, 2.5],
            &[5.0, -1.0, 0.5],
        ] {
            assert!(check_sizes(bad).is_err(), "{bad:?}");
        }
        for bad in [&[8, 4, 2][..], &[4, 4, 8], &[4, 8], &[0, 4, 8]] {
            assert!(check_steps(bad).is_err(), "{bad:?}");
        }
        let e = check_sizes(&[6.0, 10.0, 12.0]).unwrap_err().to_string();
        assert!(
            e.starts_with("--sizes 6,10,12: expected element sizes coarse to fine"),
            "{e}"
        );
    }
}
