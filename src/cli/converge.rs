//! `wovenform converge SCENE.toml --out DIR`: the mesh and step ladders, their errors and cost,
//! the table, the CSV and the error-against-time chart.

use std::path::PathBuf;

use clap::Args;

use super::progress::stderr_bar;
use super::scene_args::SceneFileArgs;
use super::{CliError, outputs};
use wovenform::publish;
use wovenform::report::converge as report;
use wovenform::study::converge as study;

#[derive(Args, Debug)]
pub struct ConvergeArgs {
    #[command(flatten)]
    pub scene: SceneFileArgs,
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
    let file = &args.scene.scene;
    let scene = args.scene.load()?;
    let ladders = study::Ladders::new(&scene, &args.sizes, &args.steps)
        .map_err(|e| CliError::bad_input(e.to_string()))?;
    let files = outputs::in_dir(&args.out, &["converge.png", "converge.csv"]);
    let inputs = outputs::scene_inputs(Some(file), &scene);
    outputs::prepare(&args.out, &files, &inputs)?;
    let bar = stderr_bar(
        ladders.len() as u64,
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} solves, {msg}",
    );
    let mut tick = |r: &study::Rung| {
        bar.inc(1);
        bar.set_message(format!(
            "last: {} mm, {} steps, {:.1} s",
            r.element_size_mm, r.steps, r.wall_s
        ));
    };
    let mesh = study::mesh_ladder(&scene, &ladders.sizes_mm, &mut tick);
    let steps = study::step_ladder(&scene, &ladders.steps, &mut tick);
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
