use wovenform::core::drawing::*;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let mut p = DrawingProblem::paper_box(args[0], args[1], args[2]);
    p.fabric.undulation = false;
    p.solver.record_residuals = true;
    if let Ok(k) = std::env::var("WF_KAPPA") {
        p.solver.stabilisation = k.parse().unwrap();
    }
    let res = solve(&p, &mut |_| {});
    println!(
        "{:?} steps {} its {}",
        res.failure, res.stats.steps, res.stats.newton_iterations
    );
    let n = res.stats.residuals.len();
    for k in [n / 4, n / 2, n / 2 + 1, 3 * n / 4, n - 2] {
        let h = &res.stats.residuals[k];
        println!(
            "{k}: {:?}",
            h.iter().map(|v| format!("{v:.1e}")).collect::<Vec<_>>()
        );
    }
}
