use wovenform::core::drawing::*;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let (r, rp, rm) = (args[0], args[1], args[2]);
    let mut p = DrawingProblem::paper_box(r, rp, rm);
    if args.len() > 3 {
        p.stroke = args[3];
    }
    if args.len() > 4 {
        p.element_size = args[4];
    }
    let res = solve(&p, &mut |l| eprint!("\r{:.3}", l));
    eprintln!();
    let (e, s) = res.max_shear();
    println!("converged {} failure {:?}", res.converged, res.failure);
    println!(
        "stroke {:.2} max shear {:.1} at {:?} tension {:.1} force {:.1} pen {:.4} drawin {:.2} dofs {} steps {} cut {} newton {} wall {:.2}s stab {:.2e} stabF {:.2e} mech {}",
        res.stroke_reached_mm,
        s,
        res.element_centre(e),
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
        res.stats.stabilisation_force_ratio,
        res.stats.mechanism
    );
    println!(
        "asm {:.2} nodal {:.2} fs {:.2}",
        res.stats.assembly_s, res.stats.nodal_s, res.stats.factor_solve_s
    );
}
