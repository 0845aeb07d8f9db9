//! `wovenform fit DATA.csv --bias HxW`: the shear law `[k1, k3, k5]` from a measured
//! bias-extension curve; writes `fabric.toml` (the scene with the fitted fabric) and the
//! test's curve, plot and shear map with the fitted law, the data on the plot.

use std::path::{Path, PathBuf};

use super::progress::stderr_bar;
use super::{CliError, outputs};
use wovenform::files::Input;
use wovenform::scene::{Scene, SceneError, specimen};
use wovenform::study::fit::refine::{
    FE_POINTS, Refined, fitted_fabric_toml, refine, usable_points,
};
use wovenform::study::fit::shear::{BiasPoint, BiasSpecimen, ShearFit, read_bias_curve};

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

pub fn exec(scene: &Scene, args: BiasFitArgs) -> Result<(), CliError> {
    let bad = |e: String| CliError::bad_input(e);
    let specimen = check(scene, &args)?;
    let data = args.data.display().to_string();
    let points = read_bias_curve(args.data).map_err(|e| bad(e.to_string()))?;
    let used = usable_points(&specimen, &points, &data).map_err(|e| bad(e.to_string()))?;
    let dir = (args.out.clone()).unwrap_or_else(|| outputs::default_dir("fit-bias-", args.data));
    let toml_path = dir.join("fabric.toml");
    prepare(scene, &args, &dir, &toml_path)?;
    let refined = refine_shown(scene, &args, &specimen, &used, &data)?;
    report(&specimen, &refined, args.refine);
    let measured: Vec<(f64, f64)> = (points.iter())
        .map(|p| (p.displacement_mm, p.force_n))
        .collect();
    let (problem, result) = (&refined.problem, &refined.result);
    let locking = scene.fabric.locking_angle_deg;
    let mut files =
        wovenform::publish::write_bias(&dir, problem, result, locking, Some(&measured))?;
    let from = (args.scene_file.as_ref()).map_or("the paper's glass fabric".to_string(), |p| {
        p.display().to_string()
    });
    let header = format!(
        "# The fabric of {from} with the shear law fitted to {data} ({} × {} mm bias extension).",
        specimen.length, specimen.width,
    );
    let text = fitted_fabric_toml(scene, &refined.fit, &header);
    files.push(wovenform::publish::write_text(&toml_path, &text)?);
    for f in &files {
        println!("{}", f.display());
    }
    Ok(())
}

/// The output folder made ready: the test's files and `fabric.toml` at `toml_path`, none over
/// the scene, its tools or the measured curve.
fn prepare(
    scene: &Scene,
    args: &BiasFitArgs,
    dir: &Path,
    toml_path: &Path,
) -> Result<(), CliError> {
    let mut inputs = outputs::scene_inputs(args.scene_file.as_deref(), scene);
    inputs.push(Input::new(args.data, "the measured bias-extension curve"));
    let mut files = super::bias::bias_outputs(dir);
    files.push(toml_path.to_path_buf());
    outputs::prepare(dir, &files, &inputs)
}

/// The refined fit, its passes on a progress bar.
fn refine_shown(
    scene: &Scene,
    args: &BiasFitArgs,
    specimen: &BiasSpecimen,
    used: &[BiasPoint],
    data: &str,
) -> Result<Refined, CliError> {
    let template = "{spinner} [{elapsed_precise}] {bar:40} {msg}";
    let bar = stderr_bar(args.refine as u64, template);
    let mut on_pass = |pass: usize| {
        bar.set_position(pass as u64);
        bar.set_message(format!("finite-element test, pass {}", pass + 1));
    };
    let (passes, h) = (args.refine, args.element_size);
    let refined = refine(scene, specimen, used, passes, h, data, &mut on_pass)
        .map_err(|e| CliError::bad_input(e.to_string()))?;
    bar.finish_and_clear();
    Ok(refined)
}

/// The specimen and the fit's options, checked against their bounds (the data's stroke is
/// checked with the data).
fn check(scene: &Scene, args: &BiasFitArgs) -> Result<BiasSpecimen, CliError> {
    let [length, width] = args.specimen;
    let specimen = BiasSpecimen {
        length,
        width,
        max_shear_deg: args.max_shear_deg.unwrap_or(scene.fabric.locking_angle_deg),
        from_mm: args.from_mm,
    };
    let to_bad = |e: SceneError| {
        CliError::bad_input(
            e.to_string()
                .replace("--length", "--bias length")
                .replace("--width", "--bias width"),
        )
    };
    specimen::check_sizes([length, width, 1.0], args.element_size, FE_POINTS).map_err(to_bad)?;
    specimen::check_fit_options(specimen.max_shear_deg, specimen.from_mm, args.refine)
        .map_err(to_bad)?;
    Ok(specimen)
}

fn show_k(fit: &ShearFit) -> String {
    fit.law
        .k
        .iter()
        .map(|k| format!("{k:.5}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn report(s: &BiasSpecimen, r: &Refined, refine: usize) {
    let fit = &r.fit;
    println!(
        "ideal kinematics: k = [{}] N·mm/mm², RMS {:.1} % ({:.3} N) over {} points",
        show_k(&r.ideal),
        100.0 * r.ideal.rms_rel,
        r.ideal.rms_n,
        r.ideal.points
    );
    println!(
        "specimen     {} mm long × {} mm wide; {} points from {} mm up to {}° of ideal central shear",
        s.length, s.width, fit.points, s.from_mm, s.max_shear_deg
    );
    for (j, name) in ["k1", "k3", "k5"].iter().enumerate() {
        println!(
            "{name}           {:.6} N·mm/mm² ({})",
            fit.law.k[j],
            k_note(fit, j)
        );
    }
    println!(
        "fit          RMS {:.1} % ({:.3} N) against the ideal kinematics' force with the refined ratio",
        100.0 * fit.rms_rel,
        fit.rms_n
    );
    println!(
        "model        the finite-element test with this law: RMS {:.1} % against the data over {} points ({} refining passes)",
        100.0 * r.model_rms_rel,
        r.model_points,
        refine
    );
    if let Some(f) = &r.result.failure {
        println!("warning      the finite-element test stopped short: {f}");
    }
}

/// How well coefficient `j` is known.
fn k_note(fit: &ShearFit, j: usize) -> String {
    if fit.at_bound[j] {
        "held at 0: free, it would make the moment fall".to_string()
    } else if fit.identified(j) {
        format!("± {:.0} %", 100.0 * fit.rel_uncertainty[j])
    } else {
        format!(
            "± {:.0} %: not identified by these data",
            100.0 * fit.rel_uncertainty[j]
        )
    }
}
