//! Wrinkles (beyond the paper) in drawings: a folding corner followed to the full stroke, and
//! the holder's process window. (Where a bias strip with a shear law stops trellising and
//! buckles, against the estimate of `wovenform::guide::bending`, is checked beside the strip,
//! in `core::specimens::bias_wrinkle`.)

use wovenform::core::fabric::shear::ShearLaw;
use wovenform::core::wrinkles::trigger::Trigger;

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
        p.element_size_mm = 5.0;
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

/// A drawing that buckles (`presets/cup.toml`: the woven law, the fitted shear law with its
/// locking, bending; it wrinkles at 0° and 90° where the fabric enters the die): a mesh too
/// coarse to follow the wrinkle holds the fabric flat, so the figure grows with refinement, and
/// each level's band must reach the fine run's figure (`guide::bending`, "The bands, measured
/// on drawings that buckle").
#[test]
fn on_a_cup_that_wrinkles_each_levels_band_reaches_the_fine_figure() {
    use wovenform::accuracy::Accuracy;
    use wovenform::scene::Scene;
    let preset = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/cup.toml");
    let scene = Scene::load(Some(&preset), &[]).unwrap();
    let figure = |level: Accuracy| {
        let mut p = scene.to_problem();
        p.element_size_mm = level.element_size_mm();
        let r = wovenform::core::drawing::solve(&p, &mut |_| {});
        assert!(r.converged, "{level}: {:?}", r.failure);
        r.max_wrinkle().unwrap().0
    };
    let fine = figure(Accuracy::Fine);
    assert!(fine > 0.5, "the cup wrinkles: {fine} mm at fine");
    for level in [Accuracy::Coarse, Accuracy::Standard] {
        let read = figure(level);
        let band = level.error().wrinkle_mm(read);
        assert!(read < fine, "{level}: {read} mm, under fine's {fine} mm");
        assert!(
            (fine - read).abs() <= band,
            "{level}: {read} mm ± {band} mm against fine's {fine} mm"
        );
    }
}
