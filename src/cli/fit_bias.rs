//! `wovenform fit DATA.csv --bias HxW`: the shear law `[k1, k3, k5]` from a measured
//! bias-extension curve; writes `fabric.toml` (the scene with the fitted fabric) and the
//! test's curve, plot and shear map with the fitted law, the data on the plot.

use std::path::{Path, PathBuf};

use super::progress::stderr_bar;
use super::{CliError, outputs};
use wovenform::core::bias::{BiasProblem, BiasResult, ideal_force, kinematic_limit};
use wovenform::files::{Input, Output};
use wovenform::scene::{Scene, specimen};
use wovenform::study::fit::shear::{
    BiasPoint, BiasSpecimen, ShearFit, fit_points, fit_shear_law, read_bias_curve,
};

/// `HxW` (or `WxH`: the longer side is the length), mm.
pub fn parse_specimen(text: &str) -> Result<[f64; 2], String> {
    let parts: Vec<&str> = text.split(['x', 'X', '×']).map(str::trim).collect();
    let sides: Vec<f64> = parts
        .iter()
        .filter_map(|p| p.parse::<f64>().ok())
        .filter(|v| v.is_finite() && *v > 0.0)
        .collect();
    match sides[..] {
        [a, b] if parts.len() == 2 && a != b => Ok([a.max(b), a.min(b)]),
        _ => Err(format!(
            "{text:?}: expected the specimen's length and width in mm, e.g. 230x115 (the \
             length longer than the width)"
        )),
    }
}

/// What `fit --bias` was given besides the data.
pub struct BiasFitArgs<'a> {
    pub data: &'a Path,
    pub specimen: [f64; 2],
    pub max_shear_deg: Option<f64>,
    pub from_mm: f64,
    pub refine: usize,
    pub element_size: f64,
    pub out: Option<PathBuf>,
    /// The scene file the fabric came from (`None`: the paper's glass fabric).
    pub scene_file: Option<PathBuf>,
}

/// Increments of the finite-element test.
const FE_POINTS: usize = 30;

pub fn exec(scene: &Scene, args: BiasFitArgs) -> Result<(), CliError> {
    let bad = |e: String| CliError::bad_input(e);
    let [length, width] = args.specimen;
    let specimen = BiasSpecimen {
        length,
        width,
        max_shear_deg: args.max_shear_deg.unwrap_or(scene.fabric.locking_angle_deg),
        from_mm: args.from_mm,
    };
    // The specimen's sizes and the options first: the data's stroke is checked below.
    let to_bad = |e: wovenform::scene::SceneError| {
        bad(e
            .to_string()
            .replace("--length", "--bias length")
            .replace("--width", "--bias width"))
    };
    specimen::check_sizes([length, width, 1.0], args.element_size, FE_POINTS).map_err(to_bad)?;
    specimen::check_fit_options(specimen.max_shear_deg, specimen.from_mm, args.refine)
        .map_err(to_bad)?;
    let points = read_bias_curve(args.data).map_err(|e| bad(e.to_string()))?;
    let used = fit_points(&specimen, &points);
    if used.len() < 4 {
        return Err(bad(format!(
            "{}: {} points with a positive force from {} mm (--from) and under {}° of ideal central shear (--max-shear; d < {:.1} mm on a {length} × {width} mm specimen): expected at least 4",
            args.data.display(),
            used.len(),
            specimen.from_mm,
            specimen.max_shear_deg,
            kinematic_limit(length, width)
        )));
    }
    let dir = (args.out.clone()).unwrap_or_else(|| outputs::default_dir("fit-bias-", args.data));
    let mut inputs = outputs::scene_inputs(args.scene_file.as_deref(), scene);
    inputs.push(Input::new(args.data, "the measured bias-extension curve"));
    let mut files = super::bias::bias_outputs(&dir);
    files.push(Output::owned_if(
        dir.join("fabric.toml"),
        outputs::FABRIC_TOML_HEAD,
    ));
    outputs::prepare(&dir, &files, &inputs)?;
    let stroke = used.last().map(|p| p.displacement_mm).unwrap_or(1.0);
    let mut problem = BiasProblem {
        fabric: scene.to_cell_params(),
        shear: None,
        length,
        width,
        stroke,
        element_size: args.element_size,
        points: FE_POINTS,
        solver: scene.to_problem().solver,
    };
    let no_fit = || {
        bad(format!(
            "{}: the data carry no information on the shear law (every fit is singular)",
            args.data.display()
        ))
    };
    let mut fit = fit_shear_law(&specimen, &used, &|_| 1.0).ok_or_else(no_fit)?;
    println!(
        "ideal kinematics: k = [{}] N·mm/mm², RMS {:.1} % ({:.3} N) over {} points",
        show_k(&fit),
        100.0 * fit.rms_rel,
        fit.rms_n,
        fit.points
    );
    // Refine on the finite-element test: the data over the FE/ideal force ratio.
    let bar = stderr_bar(
        args.refine as u64,
        "{spinner} [{elapsed_precise}] {bar:40} {msg}",
    );
    let mut last: Option<BiasResult> = None;
    for pass in 0..=args.refine {
        problem.shear = Some(fit.law);
        bar.set_message(format!("finite-element test, pass {}", pass + 1));
        let result = problem.solve(&mut |_| {}).map_err(|e| bad(e.to_string()))?;
        if result.failure.is_some() || pass == args.refine {
            last = Some(result);
            break;
        }
        let ratio = fe_over_ideal(&problem, &result);
        fit = fit_shear_law(&specimen, &used, &|d| ratio(d)).ok_or_else(no_fit)?;
        bar.inc(1);
        last = Some(result);
    }
    bar.finish_and_clear();
    let result = last.expect("at least one pass");
    report(&specimen, &fit, &result, &used, args.refine);
    let measured: Vec<(f64, f64)> = points
        .iter()
        .map(|p| (p.displacement_mm, p.force_n))
        .collect();
    problem.shear = Some(fit.law);
    let mut files = wovenform::publish::write_bias(
        &dir,
        &problem,
        &result,
        scene.fabric.locking_angle_deg,
        Some(&measured),
    )?;
    let toml_path = dir.join("fabric.toml");
    let mut fitted = scene.clone();
    // Six significant figures: far below the fit's own uncertainty.
    fitted.fabric.shear_moment = Some(fit.law.k.map(|v| format!("{v:.5e}").parse().unwrap_or(v)));
    let text = format!(
        "# The fabric of {} with the shear law fitted to {} ({} × {} mm bias extension).\n{}",
        args.scene_file
            .as_ref()
            .map_or("the paper's glass fabric".to_string(), |p| p
                .display()
                .to_string()),
        args.data.display(),
        length,
        width,
        fabric_toml(&fitted)
    );
    wovenform::study::sweep::write_atomic(&toml_path, &text)?;
    files.push(toml_path);
    for f in &files {
        println!("{}", f.display());
    }
    Ok(())
}

/// The ratio of the finite-element force to the ideal force along the test, interpolated.
fn fe_over_ideal(problem: &BiasProblem, r: &BiasResult) -> impl Fn(f64) -> f64 + use<> {
    let law = problem.shear.expect("a law");
    let (h, w) = (problem.length, problem.width);
    let pairs: Vec<(f64, f64)> = r
        .displacement_mm
        .iter()
        .zip(&r.force_n)
        .filter(|(d, _)| **d > 0.0)
        .map(|(&d, &f)| {
            let ideal = ideal_force(&law, h, w, d);
            (d, if ideal > 0.0 { f / ideal } else { 1.0 })
        })
        .collect();
    move |d: f64| interpolate(&pairs, d).unwrap_or(1.0)
}

/// The piecewise-linear curve through `points` (increasing x) at `x`, held at its ends;
/// `None` for no points.
fn interpolate(points: &[(f64, f64)], x: f64) -> Option<f64> {
    let i = points.partition_point(|p| p.0 < x);
    match (i.checked_sub(1).and_then(|j| points.get(j)), points.get(i)) {
        (Some(a), Some(b)) if b.0 > a.0 => Some(a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)),
        (Some(a), _) => Some(a.1),
        (None, b) => b.map(|b| b.1),
    }
}

fn show_k(fit: &ShearFit) -> String {
    fit.law
        .k
        .iter()
        .map(|k| format!("{k:.5}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn report(s: &BiasSpecimen, fit: &ShearFit, r: &BiasResult, used: &[BiasPoint], refine: usize) {
    println!(
        "specimen     {} mm long × {} mm wide; {} points from {} mm up to {}° of ideal central shear",
        s.length, s.width, fit.points, s.from_mm, s.max_shear_deg
    );
    for (j, name) in ["k1", "k3", "k5"].iter().enumerate() {
        let note = if fit.at_bound[j] {
            "held at 0: free, it would make the moment fall".to_string()
        } else if fit.identified(j) {
            format!("± {:.0} %", 100.0 * fit.rel_uncertainty[j])
        } else {
            format!(
                "± {:.0} %: not identified by these data",
                100.0 * fit.rel_uncertainty[j]
            )
        };
        println!("{name}           {:.6} N·mm/mm² ({note})", fit.law.k[j]);
    }
    // The finite-element curve of the last pass against the data.
    let curve: Vec<(f64, f64)> = r
        .displacement_mm
        .iter()
        .copied()
        .zip(r.force_n.iter().copied())
        .collect();
    let fe = |d: f64| interpolate(&curve, d).unwrap_or(0.0);
    let rel: Vec<f64> = used
        .iter()
        .filter(|p| p.displacement_mm <= r.displacement_mm.last().copied().unwrap_or(0.0))
        .map(|p| (fe(p.displacement_mm) - p.force_n) / p.force_n)
        .collect();
    let rms = (rel.iter().map(|v| v * v).sum::<f64>() / rel.len().max(1) as f64).sqrt();
    println!(
        "fit          RMS {:.1} % ({:.3} N) against the ideal kinematics' force with the refined ratio",
        100.0 * fit.rms_rel,
        fit.rms_n
    );
    println!(
        "model        the finite-element test with this law: RMS {:.1} % against the data over {} points ({} refining passes)",
        100.0 * rms,
        rel.len(),
        refine
    );
    if let Some(f) = &r.failure {
        println!("warning      the finite-element test stopped short: {f}");
    }
}

/// The `[fabric]` table of `scene` as TOML (every key, so the file stands alone).
fn fabric_toml(scene: &Scene) -> String {
    let mut doc = toml::Table::new();
    let fabric = toml::Table::try_from(&scene.fabric).unwrap_or_default();
    doc.insert("fabric".into(), toml::Value::Table(fabric));
    toml::to_string(&doc).unwrap_or_default()
}
