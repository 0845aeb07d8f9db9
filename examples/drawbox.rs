//! Development probe: one box drawing with tool radii r rp rm [stroke] [element size].
//! WF_KAPPA sets the stabilisation, WF_LINEAR turns undulation off.
use wovenform::core::drawing::*;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let mut p = DrawingProblem::paper_box(args[0], args[1], args[2]);
    if args.len() > 3 {
        p.stroke = args[3];
    }
    if args.len() > 4 {
        p.element_size = args[4];
    }
    if let Ok(k) = std::env::var("WF_KAPPA") {
        p.solver.stabilisation = k.parse().unwrap();
    }
    if let Ok(b) = std::env::var("WF_BLANK") {
        let b: f64 = b.parse().unwrap();
        p.blank = [b, b];
    }
    if let Ok(a) = std::env::var("WF_SIDE") {
        let a: f64 = a.parse().unwrap();
        if let Tooling::Box { side, .. } = &mut p.tooling {
            *side = [a, a];
        }
    }
    if let Ok(c) = std::env::var("WF_CLEAR") {
        let c: f64 = c.parse().unwrap();
        if let Tooling::Box { clearance, .. } = &mut p.tooling {
            *clearance = c;
        }
    }
    if std::env::var("WF_NOPRED").is_ok() {
        p.solver.secant_predictor = false;
    }
    if std::env::var("WF_RELAX").is_ok() {
        p.solver.relax_every_step = true;
    }
    if std::env::var("WF_LINEAR").is_ok() {
        p.fabric.undulation = false;
    }
    let res = solve(&p, &mut |_| {});
    let (e, s) = res.max_shear();
    println!(
        "conv {} {:?} | shear {s:.2} at {:?} T {:.1} F {:.1} pen {:.4} drawin {:.2} dofs {} steps {} cut {} newton {} wall {:.2}s stabW {:.2} stabF {:.1e}",
        res.converged,
        res.failure,
        res.element_centre(e).map(|v| (v * 10.0).round() / 10.0),
        res.max_tension_n(),
        res.punch_force_n,
        res.penetration_mm,
        res.draw_in_mm,
        res.dofs,
        res.stats.steps,
        res.stats.cutbacks,
        res.stats.newton_iterations,
        res.wall_s,
        res.stats.stabilisation_share(),
        res.stats.stabilisation_force_ratio
    );
}
