//! What the benchmarks share: the median of repeated timings, and a preset as a problem on one
//! thread.

/// The median of `v` (the mean of the middle two for an even count).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// A preset as a problem on one thread, with overrides (`KEY=VALUE`).
pub fn preset(text: &str, name: &str, overrides: &[&str]) -> crate::core::drawing::DrawingProblem {
    let overrides: Vec<crate::scene::Override> = overrides
        .iter()
        .map(|o| o.parse().expect("a valid override"))
        .collect();
    let scene = crate::scene::Scene::from_toml_str(text, name, &overrides)
        .expect("the embedded preset is valid");
    let mut p = scene.to_problem();
    p.solver.parallel = false;
    p
}
