//! `wovenform cantilever SCENE.toml --length L --width W [--json]`: the heavy cantilever of the
//! scene's fabric (Peirce; ASTM D1388), with `fabric.bending_rigidity` and `fabric.areal_mass`:
//! the tip's deflection and angles, and the bending length that checks B against a
//! measured one; writes cantilever.png (the strip from the side against the heavy elastica).

use clap::Args;
use serde::Serialize;

use super::scene_args::{OutArgs, SceneFileArgs};
use super::{CliError, outputs};
use wovenform::core::specimens::cantilever::{
    CantileverProblem, CantileverResult, peirce_rigidity,
};
use wovenform::scene::{Override, specimen};
use wovenform::show::{Fixed, Num};

#[derive(Args, Debug)]
pub struct CantileverArgs {
    // Of the scene, its fabric (with `fabric.bending_rigidity` and `fabric.areal_mass`) is used.
    #[command(flatten)]
    pub scene: SceneFileArgs,
    /// Overhang of the strip beyond the clamp, mm.
    #[arg(long, value_name = "L")]
    pub length: f64,
    /// Width of the strip, mm.
    #[arg(long, value_name = "W", default_value_t = 25.0)]
    pub width: f64,
    /// Element size along the strip, mm.
    #[arg(long, default_value_t = 1.0, value_name = "MM")]
    pub element_size: f64,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub out: OutArgs,
}

#[derive(Serialize)]
struct CantileverOutput {
    length_mm: f64,
    width_mm: f64,
    bending_rigidity_nmm: [f64; 2],
    areal_mass_g_m2: f64,
    /// Peirce's bending length `(B/w)^{1/3}` of the warp, mm.
    bending_length_mm: f64,
    tip_deflection_mm: f64,
    tip_reach_mm: f64,
    tip_angle_deg: f64,
    chord_angle_deg: f64,
    /// The rigidity Peirce's formula reads from this run's chord angle, N·mm.
    peirce_rigidity_nmm: f64,
    newton_iterations: u32,
    converged: bool,
    failure: Option<String>,
    wall_s: f64,
    files: Vec<String>,
}

/// The test the arguments and the scene describe, every bound checked before any work; an
/// error names the option, or the key and who set it (a `--set`, else the scene file).
fn problem(
    args: &CantileverArgs,
    scene: &wovenform::scene::Scene,
) -> Result<CantileverProblem, CliError> {
    let overrides = (args.scene.set.set.iter())
        .map(|s| s.parse::<Override>())
        .collect::<Result<Vec<_>, _>>()?;
    let origin = args.scene.scene.display().to_string();
    let origin_of = |keys: &[&str]| wovenform::scene::blame(&overrides, &origin, keys);
    let size = [args.length, args.width];
    Ok(specimen::cantilever_problem(
        scene,
        size,
        args.element_size,
        &origin_of,
    )?)
}

pub fn exec(args: CantileverArgs) -> Result<(), CliError> {
    let file = &args.scene.scene;
    let scene = args.scene.load()?;
    let problem = problem(&args, &scene)?;
    let (rigidity, mass) = (problem.bending_rigidity, problem.areal_mass_g_m2);
    let dir = args.out.dir("cantilever-", file);
    let inputs = outputs::scene_inputs(Some(file), &scene);
    outputs::prepare(&dir, &outputs::in_dir(&dir, &["cantilever.png"]), &inputs)?;
    let start = std::time::Instant::now();
    let r = problem
        .solve()
        .map_err(|e| CliError::bad_input(format!("{}: {e}", file.display())))?;
    let wall_s = start.elapsed().as_secs_f64();
    let png = dir.join("cantilever.png");
    wovenform::report::cantilever::profile_chart(&problem, &r)
        .write_png(&png)
        .map_err(|e| CliError::failed(format!("{}: {e}", png.display())))?;
    let c = (rigidity[0] / r.areal_weight_n_mm2).cbrt();
    let peirce = peirce_rigidity(
        args.length,
        r.chord_angle_deg.to_radians(),
        r.areal_weight_n_mm2,
    );
    if args.json {
        print_json(&args, &problem, c, peirce, &r, wall_s, &png);
    } else {
        print_text(&args, rigidity[0], mass, c, peirce, &r, wall_s);
        println!();
        println!("{}", png.display());
    }
    match &r.failure {
        Some(f) => Err(CliError::failed(format!("{}: {f}", file.display()))),
        None => Ok(()),
    }
}

/// The test's figures as one JSON object on stdout.
fn print_json(
    args: &CantileverArgs,
    problem: &CantileverProblem,
    c: f64,
    peirce: f64,
    r: &CantileverResult,
    wall_s: f64,
    png: &std::path::Path,
) {
    let (rigidity, mass) = (problem.bending_rigidity, problem.areal_mass_g_m2);
    let out = CantileverOutput {
        length_mm: args.length,
        width_mm: args.width,
        bending_rigidity_nmm: rigidity,
        areal_mass_g_m2: mass,
        bending_length_mm: c,
        tip_deflection_mm: r.tip_deflection_mm,
        tip_reach_mm: r.tip_reach_mm,
        tip_angle_deg: r.tip_angle_deg,
        chord_angle_deg: r.chord_angle_deg,
        peirce_rigidity_nmm: peirce,
        newton_iterations: r.newton_iterations,
        converged: r.failure.is_none(),
        failure: r.failure.as_ref().map(|f| f.to_string()),
        wall_s,
        files: vec![png.display().to_string()],
    };
    println!("{}", serde_json::to_string(&out).expect("plain data"));
}

fn print_text(
    args: &CantileverArgs,
    b: f64,
    mass: f64,
    c: f64,
    peirce: f64,
    r: &CantileverResult,
    wall_s: f64,
) {
    println!(
        "strip        {} mm overhang × {} mm, B = {} N·mm, {} g/m² (bending length c = {} mm)",
        Num(args.length),
        Num(args.width),
        Num(b),
        Num(mass),
        Fixed(c, 2)
    );
    println!(
        "tip          {:.3} mm below the clamp, {:.3} mm out; its slope {:.2}°, the chord {:.2}°",
        r.tip_deflection_mm, r.tip_reach_mm, r.tip_angle_deg, r.chord_angle_deg
    );
    println!(
        "Peirce       this chord reads B = {} N·mm ((L/c)³ = 8 tan φ / cos(φ/2)); the \
         standard overhang, 41.5° of chord, is at L = 2c = {} mm",
        Fixed(peirce, 4),
        Fixed(2.0 * c, 1)
    );
    println!(
        "solver       {} Newton iterations, {} load steps, {wall_s:.2} s",
        r.newton_iterations, r.steps
    );
}
