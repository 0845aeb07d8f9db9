//! `wovenform bias SCENE.toml --length H --width W --stroke D`: the bias-extension test of the
//! scene's fabric; writes bias.csv, bias.png and shear.png, prints a summary or JSON.

use std::path::{Path, PathBuf};

use clap::Args;
use serde::Serialize;

use super::progress::stderr_bar;
use super::scene_args::{OutArgs, SceneFileArgs};
use super::{CliError, outputs};
use wovenform::core::specimens::bias::{BiasProblem, BiasResult, kinematic_limit};
use wovenform::report::bias::{Departure, departure};
use wovenform::scene::specimen;

#[derive(Args, Debug)]
pub struct BiasArgs {
    // Of the scene, its fabric (with `fabric.shear_moment`) and numerics are used.
    #[command(flatten)]
    pub scene: SceneFileArgs,
    /// Free length of the specimen between the grips, mm.
    #[arg(long, value_name = "H")]
    pub length: f64,
    /// Width of the specimen, mm (less than the length; usually half).
    #[arg(long, value_name = "W")]
    pub width: f64,
    /// Grip displacement at the end, mm (less than (√2 − 1)(H − W)).
    #[arg(long, value_name = "D")]
    pub stroke: f64,
    #[command(flatten)]
    pub out: OutArgs,
    /// Print one JSON object (the curve's arrays and the departure from the ideal kinematics).
    #[arg(long)]
    pub json: bool,
    /// Points of the curve (equal displacement increments).
    #[arg(long, default_value_t = 40, value_name = "N")]
    pub points: usize,
    /// Element size along the yarns, mm (the scene's mesh.element_size is for drawing; the
    /// test's zones are uniform: on 120 × 60 mm, 5 mm is within 1.2 % in force and 0.15° of
    /// 2.5 mm, see wovenform::guide::shear_law).
    #[arg(long, default_value_t = 5.0, value_name = "MM")]
    pub element_size: f64,
}

#[derive(Serialize)]
struct BiasOutput<'a> {
    length_mm: f64,
    width_mm: f64,
    stroke_mm: f64,
    shear_moment: [f64; 3],
    displacement_mm: &'a [f64],
    force_n: &'a [f64],
    shear_centre_deg: &'a [f64],
    /// Largest |γ − γ_ideal| at the centre (°) and where (mm); RMS and largest relative
    /// departure of the force from the ideal kinematics' force.
    departure_shear_deg: f64,
    departure_shear_at_mm: f64,
    departure_force_rms: f64,
    departure_force_max: f64,
    converged: bool,
    failure: Option<String>,
    wall_s: f64,
    files: Vec<String>,
}

pub fn exec(args: BiasArgs) -> Result<(), CliError> {
    let file = &args.scene.scene;
    let scene = args.scene.load()?;
    let size = [args.length, args.width, args.stroke];
    let problem = specimen::bias_problem(&scene, size, args.element_size, args.points)
        .map_err(|e| CliError::bad_input(format!("{}: {e}", file.display())))?;
    let dir = args.out.dir("bias-", file);
    let inputs = outputs::scene_inputs(Some(file), &scene);
    outputs::prepare(&dir, &bias_outputs(&dir), &inputs)?;
    let (result, wall_s) = pull(&problem)?;
    let locking = scene.fabric.locking_angle_deg;
    let files = wovenform::publish::write_bias(&dir, &problem, &result, locking, None)?;
    let dep = departure(&problem, &result);
    if args.json {
        print_json(&problem, &result, &dep, wall_s, &files);
    } else {
        print_text(&problem, &result, &dep, wall_s, &files);
    }
    match &result.failure {
        Some(f) => Err(CliError::failed(format!(
            "{}: the pull stopped at {:.2} of {} mm: {f}",
            file.display(),
            result.displacement_mm.last().copied().unwrap_or(0.0),
            problem.stroke
        ))),
        None => Ok(()),
    }
}

/// The test solved with a progress bar, and its wall time, s.
fn pull(problem: &BiasProblem) -> Result<(BiasResult, f64), CliError> {
    let bar = stderr_bar(1000, "{spinner} [{elapsed_precise}] {bar:40} {msg}");
    bar.set_message(format!("pulling to {} mm", problem.stroke));
    let start = std::time::Instant::now();
    let result = problem
        .solve(&mut |f| bar.set_position((f * 1000.0).round() as u64))
        .map_err(|e| CliError::bad_input(e.to_string()))?;
    bar.finish_and_clear();
    Ok((result, start.elapsed().as_secs_f64()))
}

/// What `bias` and `fit --bias` write into `dir`.
pub fn bias_outputs(dir: &Path) -> Vec<PathBuf> {
    outputs::in_dir(dir, &["bias.png", "shear.png", "bias.csv"])
}

fn print_json(p: &BiasProblem, r: &BiasResult, dep: &Departure, wall_s: f64, files: &[PathBuf]) {
    let out = BiasOutput {
        length_mm: p.length,
        width_mm: p.width,
        stroke_mm: p.stroke,
        shear_moment: p.shear.map(|s| s.k).unwrap_or_default(),
        displacement_mm: &r.displacement_mm,
        force_n: &r.force_n,
        shear_centre_deg: &r.shear_centre_deg,
        departure_shear_deg: dep.shear_deg,
        departure_shear_at_mm: dep.shear_at_mm,
        departure_force_rms: dep.force_rms_rel,
        departure_force_max: dep.force_max_rel,
        converged: r.failure.is_none(),
        failure: r.failure.as_ref().map(|f| f.to_string()),
        wall_s,
        files: files.iter().map(|f| f.display().to_string()).collect(),
    };
    println!("{}", serde_json::to_string(&out).expect("plain data"));
}

fn print_text(p: &BiasProblem, r: &BiasResult, dep: &Departure, wall_s: f64, files: &[PathBuf]) {
    let last = r.displacement_mm.len() - 1;
    println!(
        "specimen     {} × {} mm, yarns at ±45°, pulled {} mm (the ideal kinematics end at {:.1} mm)",
        p.length,
        p.width,
        p.stroke,
        kinematic_limit(p.length, p.width)
    );
    println!(
        "end          force {:.3} N at {:.2} mm; centre shear {:.2}°",
        r.force_n[last], r.displacement_mm[last], r.shear_centre_deg[last]
    );
    println!(
        "kinematics   centre shear departs from the ideal by up to {:.2}° (at {:.1} mm); force by {:.1} % RMS, {:.1} % at most (past 1 mm)",
        dep.shear_deg,
        dep.shear_at_mm,
        100.0 * dep.force_rms_rel,
        100.0 * dep.force_max_rel
    );
    println!(
        "solver       {} points, {} Newton iterations, {wall_s:.2} s; {} elements",
        last,
        r.newton_iterations,
        r.mesh.quads.len()
    );
    println!();
    for f in files {
        println!("{}", f.display());
    }
}
