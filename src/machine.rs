//! What the machine the program runs on allows: the memory a run may take, whether a drawing
//! fits in it, and a single run's threads.

use crate::core::drawing::DrawingProblem;
use crate::show::{Num, show_bytes};

/// The memory one run may take, bytes: 80 % of what the system reported available
/// (`MemAvailable` in `/proc/meminfo`) when first asked, or of 10 GiB where it does not say.
/// Read once per process: every scene's validation asks (each keystroke in the explorer, each
/// design of a sweep).
pub fn memory_budget_bytes() -> f64 {
    static BUDGET: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *BUDGET.get_or_init(|| {
        let available = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|text| {
                text.lines()
                    .find(|l| l.starts_with("MemAvailable:"))
                    .and_then(|l| l.split_whitespace().nth(1))
                    .and_then(|kb| kb.parse::<f64>().ok())
            })
            .map(|kb| kb * 1024.0);
        0.8 * available.unwrap_or(10.0 * GIB)
    })
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Why a drawing does not fit in the memory a run may take: what it would need, what may be
/// used, and which element size would fit.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "mesh.element_size = {} mm on a {} × {} mm blank: {} elements ({} solved) would need {}, but a run may use at most {} on this machine (80 % of what is available): {advice}",
    Num(*element_size_mm),
    Num(blank_mm[0]),
    Num(blank_mm[1]),
    count(*elements),
    if *quarter { "a quarter" } else { "the full blank" },
    need(*need_bytes),
    show_bytes(*budget_bytes)
)]
pub struct TooLarge {
    pub element_size_mm: f64,
    pub blank_mm: [f64; 2],
    /// Elements of the solved part (infinite: too many to count).
    pub elements: f64,
    /// A quarter of the blank is solved, not the whole.
    pub quarter: bool,
    /// The model's estimated memory (infinite: unbounded), and what a run may use, bytes.
    pub need_bytes: f64,
    pub budget_bytes: f64,
    pub advice: Advice,
}

/// What would make a drawing fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Advice {
    ElementSize {
        min_element_size_mm: f64,
    },
    /// No element size up to a quarter of the blank's shorter side fits.
    SmallerBlank,
}

impl std::fmt::Display for Advice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Advice::ElementSize {
                min_element_size_mm,
            } => write!(
                f,
                "expected mesh.element_size ≥ {min_element_size_mm:.3} mm for this blank"
            ),
            Advice::SmallerBlank => f.write_str("expected a smaller blank.size"),
        }
    }
}

/// Why a drawing does not fit: alone, or in its share of the budget among runs at once.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FitError {
    #[error(transparent)]
    Alone(TooLarge),
    #[error(
        "{alone} (its share: {runs} designs run at once share the budget of {}; fewer --jobs give each more)",
        show_bytes(*budget_bytes)
    )]
    Shared {
        /// The drawing against its share of the budget.
        alone: TooLarge,
        runs: usize,
        budget_bytes: f64,
    },
}

fn count(elements: f64) -> String {
    if elements.is_finite() {
        format!("{elements:.2e}")
    } else {
        "too many".to_string()
    }
}

fn need(bytes: f64) -> String {
    if bytes.is_finite() {
        format!("about {} of memory", show_bytes(bytes))
    } else {
        "unbounded memory".to_string()
    }
}

/// Whether `problem`'s model fits in `budget` bytes (the estimate of
/// [`DrawingProblem::size_estimate`]); otherwise what it would need and which element size would
/// fit.
pub fn check_fits(problem: &DrawingProblem, budget: f64) -> Result<(), TooLarge> {
    let size = problem.size_estimate();
    if size.bytes <= budget {
        return Ok(());
    }
    // The smallest element size that fits, by bisection (the estimate falls with h).
    let fits = |h: f64| {
        let mut p = problem.clone();
        p.element_size_mm = h;
        p.size_estimate().bytes <= budget
    };
    let (mut lo, mut hi) = (
        problem.element_size_mm,
        0.25 * problem.blank_mm[0].min(problem.blank_mm[1]),
    );
    let advice = if fits(hi) {
        for _ in 0..60 {
            let mid = (lo * hi).sqrt();
            if fits(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Advice::ElementSize {
            min_element_size_mm: hi * 1.0005,
        }
    } else {
        Advice::SmallerBlank
    };
    Err(TooLarge {
        element_size_mm: problem.element_size_mm,
        blank_mm: problem.blank_mm,
        elements: size.elements,
        quarter: problem.quarter_applies(),
        need_bytes: size.bytes,
        budget_bytes: budget,
        advice,
    })
}

/// Whether `problem` fits in its share of `budget` when `runs` drawings (a sweep's designs on
/// `--jobs` threads) are solved at once; the error of [`check_fits`] with the share.
pub fn check_fits_among(
    problem: &DrawingProblem,
    budget: f64,
    runs: usize,
) -> Result<(), FitError> {
    let runs = runs.max(1);
    check_fits(problem, budget / runs as f64).map_err(|alone| {
        if runs == 1 {
            FitError::Alone(alone)
        } else {
            FitError::Shared {
                alone,
                runs,
                budget_bytes: budget,
            }
        }
    })
}

/// Runs `work` (a single drawing, whose elements are evaluated in parallel) on a worker of
/// rayon's pool, as `core::sparse::linear` runs faer's factorization. Asked for from outside the pool,
/// each parallel loop is handed to the pool and waited for, every assembly again; from inside,
/// the asking thread starts on it at once. On a 2-core machine (2026-12-06) the open box at fine
/// took 0.89–0.91× the time of one thread with the parallel assembly asked for from outside the
/// pool, and 0.95–1.04× from inside (`bench --scaling`, three runs each); as `wovenform run`
/// solves it, 0.95× the time of the old way in the median of ten pairs.
pub fn on_pool<R: Send>(work: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| work())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_single_run_is_solved_on_a_worker_of_the_pool_to_the_same_figures() {
        assert!(on_pool(|| rayon::current_thread_index().is_some()));
        let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
        p.element_size_mm = 10.0;
        p.solver.parallel = true;
        let outside = crate::core::drawing::solve(&p, &mut |_| {});
        let inside = on_pool(|| crate::core::drawing::solve(&p, &mut |_| {}));
        assert!(outside.converged && inside.converged);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&outside.shear_deg), bits(&inside.shear_deg));
        assert_eq!(
            outside.punch_force_n.to_bits(),
            inside.punch_force_n.to_bits()
        );
        assert_eq!(
            outside.stats.newton_iterations,
            inside.stats.newton_iterations
        );
    }

    #[test]
    fn the_budget_is_positive() {
        assert!(memory_budget_bytes() > 0.0);
    }

    #[test]
    fn designs_run_at_once_share_the_budget() {
        let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
        p.element_size_mm = 1.0;
        let need = p.size_estimate().bytes;
        let budget = 1.5 * need;
        assert!(check_fits_among(&p, budget, 1).is_ok());
        let why = check_fits_among(&p, budget, 2).unwrap_err().to_string();
        assert!(why.starts_with("mesh.element_size = 1 mm"), "{why}");
        assert!(
            why.contains("2 designs run at once") && why.contains("--jobs"),
            "{why}"
        );
    }
}
