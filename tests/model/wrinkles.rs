//! Wrinkles (beyond the paper): where a bias strip with a shear law stops trellising and
//! buckles (`core::specimens::bias_wrinkle`) against the estimate of `wovenform::guide::bending`, and the
//! wrinkle verdict of a drawing that does not hang on its trigger.

use wovenform::core::fabric::law::CellParams;
use wovenform::core::fabric::shear::ShearLaw;
use wovenform::core::solver::SolverOptions;
use wovenform::core::specimens::bias_wrinkle::{BiasWrinkleProblem, BiasWrinkleResult};
use wovenform::core::wrinkles::trigger::Trigger;

/// A 60 × 30 mm bias strip of the glass fabric's fitted shear law with locking at 60°,
/// B = 1 N·mm, compressive yarns of 1 % of C, 2.5 mm elements, shortened by 3 mm in 30 points.
fn strip(trigger_pa: f64) -> BiasWrinkleProblem {
    let mut fabric = CellParams::PAPER_GLASS;
    fabric.undulation = false;
    BiasWrinkleProblem {
        fabric,
        shear: ShearLaw::new([0.0376068, -0.0786365, 0.0822838]).with_locking(60.0),
        bending_rigidity: [1.0, 1.0],
        compression: [1e-2, 1e-2],
        length: 60.0,
        width: 30.0,
        element_size: 2.5,
        shortening_mm: 3.0,
        points: 30,
        trigger: Trigger {
            pressure_mpa: trigger_pa * 1e-6,
            seed: 1,
        },
        solver: SolverOptions::default(),
    }
}

/// The first point whose wrinkle passes 0.5 mm.
fn onset(r: &BiasWrinkleResult) -> usize {
    (r.wrinkle_mm.iter().position(|w| *w > 0.5)).expect("the strip buckles")
}

#[test]
fn a_bias_strip_trellises_then_wrinkles_where_shearing_costs_more_than_bending() {
    let p = strip(1.0);
    let euler = p.euler_force_n();
    let r = p.solve().unwrap();
    assert!(r.failure.is_none(), "{:?}", r.failure);
    let k = onset(&r);
    // Flat while it trellises (up to 85 % of the onset's shortening: the last points before
    // it already lift), the shear growing with the shortening.
    for i in 1..k {
        let d = r.shortening_mm[i];
        if d < 0.85 * r.shortening_mm[k] {
            assert!(r.wrinkle_mm[i] < 0.1, "Δ {d}: {} mm", r.wrinkle_mm[i]);
        }
        assert!(r.shear_centre_deg[i] > r.shear_centre_deg[i - 1]);
    }
    // It buckles at a force below the beam's Euler force (an upper bound: the hinges have no
    // twisting stiffness, so the strip finds a cheaper mode), but not far below.
    let buckling = r.force_n[k];
    assert!(
        buckling > 0.6 * euler && buckling < euler,
        "{buckling} N against {euler} N"
    );
    // Past it, the force stays near that and the shear all but stops: the strip shortens by
    // wrinkling. Rate of shear per mm before and after.
    let last = r.force_n.len() - 1;
    assert!(
        (r.force_n[last] / buckling - 1.0) < 0.15,
        "{}",
        r.force_n[last]
    );
    let before = r.shear_centre_deg[k - 1] / r.shortening_mm[k - 1];
    let after = (r.shear_centre_deg[last] - r.shear_centre_deg[k + 1])
        / (r.shortening_mm[last] - r.shortening_mm[k + 1]);
    assert!(
        after < 0.25 * before,
        "{after} °/mm after against {before} before"
    );
    // Against the estimate: trellising the strip (its measured pre-buckling force, which runs
    // above the ideal kinematics' by the clamps' share) reaches the onset's force by then.
    let estimate = p.onset_estimate_mm().unwrap();
    assert!(
        r.shortening_mm[k] < estimate,
        "buckled at {} mm, estimate {estimate} mm",
        r.shortening_mm[k]
    );
    assert!(r.wrinkle_mm[last] > 5.0, "{}", r.wrinkle_mm[last]);
}

#[test]
fn the_bias_strips_wrinkles_do_not_hang_on_the_trigger() {
    let (a, b) = (strip(1.0).solve().unwrap(), strip(0.1).solve().unwrap());
    let last = a.wrinkle_mm.len() - 1;
    assert!(
        (a.wrinkle_mm[last] / b.wrinkle_mm[last] - 1.0).abs() < 0.01,
        "{} against {}",
        a.wrinkle_mm[last],
        b.wrinkle_mm[last]
    );
    assert!((onset(&a) as i64 - onset(&b) as i64).abs() <= 1);
}

/// The tight box (5/6/5 mm) with the glass fabric's shear law, locking and bending folds at its
/// corners past locking: the solver follows the buckle to the full stroke (it stopped at 24.5
/// of 28 mm before the long descent of `core::solver::DESCENT_ITERATIONS`), and a plate
/// pressed ten times harder leaves smaller wrinkles. Coarse, under a plate.
#[test]
fn a_folding_corner_is_followed_and_more_holder_force_leaves_smaller_wrinkles() {
    use wovenform::core::drawing::{Bending, DEFAULT_COMPRESSION, DrawingProblem, solve};
    let run = |force_kn: f64| {
        let mut p = DrawingProblem::paper_box(5.0, 6.0, 5.0);
        p.fabric.undulation = false;
        p.shear = Some(ShearLaw::new([0.0376068, -0.0786365, 0.0822838]).with_locking(60.0));
        p.bending = Some(Bending {
            rigidity: [0.08, 0.08],
            compression: [DEFAULT_COMPRESSION; 2],
            trigger: Trigger {
                pressure_mpa: 1e-6,
                seed: 1,
            },
        });
        p.element_size = 5.0;
        p.holder_force_n = Some(1000.0 * force_kn);
        solve(&p, &mut |_| {})
    };
    let (light, heavy) = (run(2.0), run(20.0));
    assert!(light.converged, "{:?}", light.failure);
    assert!(heavy.converged, "{:?}", heavy.failure);
    let (w_light, w_heavy) = (
        light.max_wrinkle().unwrap().0,
        heavy.max_wrinkle().unwrap().0,
    );
    assert!(
        w_light > w_heavy + 0.1,
        "{w_light} mm at 2 kN, {w_heavy} mm at 20 kN"
    );
}

/// The holder's process window (`presets/box-holder-window.toml`) at standard: too little
/// holder force leaves the corners sheared past locking, enough forms the part, too much breaks
/// yarns. Three of its nine designs: the lightest but one, a middle one, the heaviest.
#[test]
fn the_holder_window_preset_has_a_locked_side_a_window_and_a_broken_side() {
    use wovenform::summary::RunSummary;
    use wovenform::verdict::Verdict;
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/box-holder-window.toml");
    let plan = wovenform::study::sweep::Plan::load(&path, &[]).unwrap();
    let run = |pressure: f64| {
        let design = (plan.designs().into_iter())
            .find(|d| d.values[0].as_float() == Some(pressure))
            .unwrap();
        let scene = plan.design_scene(&design).unwrap();
        let mut problem = scene.to_problem();
        problem.solver.parallel = false;
        let result = wovenform::core::drawing::solve(&problem, &mut |_| {});
        RunSummary::new(&design.id, &scene, &result, 0.0)
    };
    let light = run(0.1);
    assert_eq!(
        Verdict::of_sentence(&light.verdict),
        Verdict::Infeasible,
        "{}",
        light.verdict
    );
    assert!(light.judged.over.shear(), "{}", light.verdict);
    let middle = run(2.0);
    assert_eq!(
        Verdict::of_sentence(&middle.verdict),
        Verdict::Feasible,
        "{}",
        middle.verdict
    );
    let heavy = run(10.0);
    assert_eq!(
        Verdict::of_sentence(&heavy.verdict),
        Verdict::Infeasible,
        "{}",
        heavy.verdict
    );
    assert!(
        heavy.judged.over.tension() && !heavy.judged.over.shear(),
        "{}",
        heavy.verdict
    );
}
