//! A rough wall time of one run before it starts, for a sweep's announcement and a Slurm
//! job's task count: not a promise (the radii alone move it by a factor of two).
//!
//! The figures were measured on one machine: the mean design of the paper-box preset sweep at
//! standard took 0.8 s on one core for the 1,156 elements of its solved quarter (the open box
//! 0.45 s, the tight one 1 s), and wall time grows with the solved elements to the power 1.4
//! (`bench`: wall time ∝ dofs^1.4) and with the stroke. Machines here differ 2–4× in speed, so
//! the figure is scaled by this machine's speed: the time of a fixed piece of the solver's own
//! work (law evaluations along a loading path, a few milliseconds), measured once per process,
//! over that work's time on the machine the figures come from.

use std::hint::black_box;
use std::sync::OnceLock;
use std::time::Instant;

use crate::core::fabric::law::{CellLaw, CellParams};
use crate::scene::Scene;

/// Seconds of a standard run of the mean design (1,156 solved elements, 28 mm stroke) on the
/// reference machine.
const REFERENCE_RUN_S: f64 = 0.8;
/// A run with bending against the same run without (`bench --bending`: 1.8–2.2× on the open
/// box at standard, whole blank; the hinges' couplings fill the factor).
const BENDING_COST: f64 = 2.0;
/// Seconds of [`calibration_work`] on the reference machine (median of 5, 2026-12-02).
const REFERENCE_WORK_S: f64 = 0.0085;

/// The estimated wall time of `scene`'s run on one core of this machine, s.
pub fn run_seconds(scene: &Scene) -> f64 {
    let p = scene.to_problem();
    let parts = if p.quarter_applies() { 4.0 } else { 1.0 };
    let elements = p.blank_mm[0] * p.blank_mm[1] / (p.element_size_mm * p.element_size_mm) / parts;
    let reference = REFERENCE_RUN_S * (elements / 1156.0).powf(1.4) * (p.stroke_mm / 28.0).max(0.1);
    let bending = if p.bending.is_some() {
        BENDING_COST
    } else {
        1.0
    };
    reference * bending * slowness()
}

/// This machine against the reference one (2: half as fast), measured once per process and
/// held within [0.25, 4] (a loaded moment must not make an estimate absurd).
fn slowness() -> f64 {
    static SLOWNESS: OnceLock<f64> = OnceLock::new();
    *SLOWNESS.get_or_init(|| {
        let mut times: Vec<f64> = (0..5)
            .map(|_| {
                let t = Instant::now();
                calibration_work();
                t.elapsed().as_secs_f64()
            })
            .collect();
        times.sort_by(f64::total_cmp);
        (times[2] / REFERENCE_WORK_S).clamp(0.25, 4.0)
    })
}

/// 20,000 law evaluations with tangent, each cell warm-started along a loading path, as the
/// solver calls them.
fn calibration_work() {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let mut states = vec![law.initial_state(); 200];
    for step in 0..100 {
        for (i, s) in states.iter_mut().enumerate() {
            let e1 = 2e-5 * step as f64 * (1.0 + 0.001 * i as f64);
            let r = law.evaluate(black_box([e1, e1 / (1.0 + (i % 7) as f64)]), *s);
            *s = r.crimp;
            black_box(r.dt);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_grows_with_the_elements_and_the_machine_is_measured() {
        // A fine mesh has four times the elements of standard.
        let scene = Scene::from_toml_str("", "test", &[]).unwrap();
        let mut fine = scene.clone();
        fine.mesh.element_size = 1.25;
        let ratio = run_seconds(&fine) / run_seconds(&scene);
        assert!((ratio - 4f64.powf(1.4)).abs() < 1e-9, "{ratio}");
        let s = slowness();
        assert!((0.25..=4.0).contains(&s), "{s}");
    }

    #[test]
    #[ignore = "prints the calibration work's time on this machine"]
    fn calibration_time() {
        for _ in 0..7 {
            let t = Instant::now();
            calibration_work();
            println!("{:.6}", t.elapsed().as_secs_f64());
        }
    }
}
