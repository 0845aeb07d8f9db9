//! `wovenform run SCENE.toml`: solve one scene, print its summary, write its maps, VTU and
//! summary.json.

use clap::Args;

use super::progress::stroke_bar;
use super::scene_args::{AccuracyArgs, OutArgs, SceneFileArgs};
use super::{CliError, outputs};
use wovenform::publish::{NEWTON_TRACE_FILES, RUN_FILES, write_newton_trace, write_run};
use wovenform::study::draw::{draw, draw_traced};

#[derive(Args, Debug)]
pub struct RunArgs {
    #[command(flatten)]
    pub scene: SceneFileArgs,
    #[command(flatten)]
    pub out: OutArgs,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub accuracy: AccuracyArgs,
    /// Also write every Newton iteration of the run: `newton_trace.csv` (residual, active-set
    /// changes, line search length, where the residual sits) and `newton_trace.png`.
    #[arg(long)]
    pub newton_trace: bool,
}

/// The output folder, checked before the solve so that a bad one costs nothing.
fn output_folder(
    args: &RunArgs,
    scene: &wovenform::scene::Scene,
) -> Result<std::path::PathBuf, CliError> {
    let file = &args.scene.scene;
    let dir = args.out.dir("", file);
    let mut files = outputs::in_dir(&dir, &RUN_FILES);
    if args.newton_trace {
        files.extend(outputs::in_dir(&dir, &NEWTON_TRACE_FILES));
    }
    outputs::prepare(&dir, &files, &outputs::scene_inputs(Some(file), scene))?;
    Ok(dir)
}

pub fn exec(args: RunArgs) -> Result<(), CliError> {
    let file = &args.scene.scene;
    let scene = args.scene.load_with(&args.accuracy.with(&args.scene.set))?;
    let dir = output_folder(&args, &scene)?;
    let stroke = scene.process.stroke;
    let bar = stroke_bar(stroke);
    let name = outputs::stem(file, "scene");
    let solve = if args.newton_trace { draw_traced } else { draw };
    let mut drawn = wovenform::machine::on_pool(|| {
        solve(&name, &scene, &mut |f| {
            super::progress::show_stroke(&bar, f, stroke)
        })
    });
    bar.finish_and_clear();
    if args.newton_trace {
        let stats = &drawn.result.stats;
        let title = format!(
            "Newton iterations of {name}: {} in {} load steps",
            stats.newton_iterations, stats.steps
        );
        write_newton_trace(&dir, &mut drawn.summary, stats, stroke, &title)?;
    }
    // After the trace, so that summary.json names its files too.
    let tooling = &drawn.problem.tooling;
    write_run(&dir, &mut drawn.summary, &drawn.result, tooling)?;
    if args.json {
        println!("{}", drawn.summary.to_json());
    } else {
        print!("{}", drawn.summary.to_text());
    }
    match drawn.refusal() {
        Some(why) => Err(CliError::failed(format!("{}: {why}", file.display()))),
        None => Ok(()),
    }
}
