//! `wovenform converge SCENE.toml --out DIR`: the mesh and step ladders, their errors and cost,
//! the table, the CSV and the error-against-time chart.

use std::path::PathBuf;

use clap::Args;

use super::progress::stderr_bar;
use super::scene_args::SceneArgs;
use super::{CliError, outputs};
use wovenform::publish;
use wovenform::report::converge as report;
use wovenform::study::converge as study;

#[derive(Args, Debug)]
pub struct ConvergeArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub scene: PathBuf,
    /// Override one scene key; VALUE is a TOML literal. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output folder.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Element sizes of the mesh ladder, mm, coarse to fine (default: the scene's size times
    /// 2, √2, 1, 1/√2, 1/2).
    #[arg(long, value_delimiter = ',', value_name = "MM,MM,...")]
    pub sizes: Vec<f64>,
    /// Least load-step counts of the step ladder, few to many (default 4,8,16,32,64).
    #[arg(long, value_delimiter = ',', value_name = "N,N,...")]
    pub steps: Vec<u32>,
}

pub fn exec(args: ConvergeArgs) -> Result<(), CliError> {
    let scene = SceneArgs {
        scene: Some(args.scene.clone()),
        set: args.set.clone(),
    }
    .load()?;
    let h = scene.mesh.element_size;
    let sizes = if args.sizes.is_empty() {
        [2.0, 2f64.sqrt(), 1.0, 0.5f64.sqrt(), 0.5]
            .iter()
            .map(|k| (h * k * 1000.0).round() / 1000.0)
            .collect()
    } else {
        args.sizes.clone()
    };
    let counts = if args.steps.is_empty() {
        vec![4, 8, 16, 32, 64]
    } else {
        args.steps.clone()
    };
    study::check_sizes(&sizes).map_err(|e| CliError::bad_input(e.to_string()))?;
    // Each rung is the scene at its element size: checked against the scene's bounds (and this
    // machine's memory) before any rung is solved.
    for size in &sizes {
        let set_size = format!("mesh.element_size={size}");
        let rung = SceneArgs {
            scene: Some(args.scene.clone()),
            set: [args.set.clone(), vec![set_size.clone()]].concat(),
        };
        rung.load().map_err(|e| {
            let why = e.message.replace(&format!("--set {set_size}: "), "");
            CliError::bad_input(format!("--sizes {size}: {why}"))
        })?;
    }
    study::check_steps(&counts).map_err(|e| CliError::bad_input(e.to_string()))?;
    let mut files = outputs::replaceable(&args.out, &["converge.png"]);
    let csv = args.out.join("converge.csv");
    files.push(wovenform::files::Output::owned_if(
        csv,
        outputs::CONVERGE_CSV_HEAD,
    ));
    let inputs = outputs::scene_inputs(Some(&args.scene), &scene);
    outputs::prepare(&args.out, &files, &inputs)?;
    let total = (sizes.len() + counts.len()) as u64;
    let bar = stderr_bar(
        total,
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} solves, {msg}",
    );
    let mut tick = |r: &study::Rung| {
        bar.inc(1);
        bar.set_message(format!(
            "last: {} mm, {} steps, {:.1} s",
            r.element_size_mm, r.steps, r.wall_s
        ));
    };
    let mesh = study::mesh_ladder(&scene, &sizes, &mut tick);
    let steps = study::step_ladder(&scene, &counts, &mut tick);
    bar.finish_and_clear();

    print!("{}", report::table(&mesh, &steps));
    println!(
        "\nerror against wall time (S, F: the mesh ladder's max shear in °, punch force in %; \
         s, f: the step ladder's)\n{}",
        report::text_chart(&mesh, &steps, 60, 14)
    );
    let [csv_path, png] = publish::write_converge(&args.out, &mesh, &steps)?;
    println!("wrote {} and {}", csv_path.display(), png.display());
    Ok(())
}
