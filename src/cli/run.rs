//! `wovenform run SCENE.toml`: solve one scene, print its summary, write its maps, VTU and
//! summary.json.

use std::path::{Path, PathBuf};

use clap::Args;

use super::progress::stroke_bar;
use super::scene_args::{SceneArgs, parse_accuracy, with_accuracy};
use super::{CliError, outputs};
use wovenform::accuracy::Accuracy;
use wovenform::core::drawing::{self, DrawingFailure};
use wovenform::publish::write_run;
use wovenform::summary::RunSummary;

#[derive(Args, Debug)]
pub struct RunArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub scene: PathBuf,
    /// Override one scene key; VALUE is a TOML literal, e.g. --set tools.r=7.5 or
    /// --set blank.size=[130,100]. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output folder (default: out/<scene file stem>).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub json: bool,
    /// Accuracy level: coarse (5 mm elements), standard (2.5 mm) or fine (1.25 mm); sets
    /// mesh.element_size (a --set of it wins) and reports the level's measured error.
    #[arg(long, value_name = "LEVEL", value_parser = parse_accuracy)]
    pub accuracy: Option<Accuracy>,
}

pub fn exec(args: RunArgs) -> Result<(), CliError> {
    let scene = SceneArgs {
        scene: Some(args.scene.clone()),
        set: with_accuracy(args.accuracy, &args.set),
    }
    .load()?;
    let name = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    // The output folder is checked before the solve, so a bad one costs nothing.
    let dir = args.out.unwrap_or_else(|| Path::new("out").join(&name));
    let inputs = outputs::scene_inputs(Some(&args.scene), &scene);
    let mut files = outputs::replaceable(&dir, &wovenform::publish::RUN_FILES[1..]);
    files.push(wovenform::files::Output::owned_if(
        dir.join("summary.json"),
        outputs::SUMMARY_JSON_HEAD,
    ));
    outputs::prepare(&dir, &files, &inputs)?;
    let problem = scene.to_problem();
    let bar = stroke_bar(problem.stroke);
    let start = std::time::Instant::now();
    let result = drawing::solve(&problem, &mut |fraction| {
        bar.set_position((fraction * 1000.0).round() as u64);
        bar.set_message(format!(
            "stroke {:.2} of {} mm",
            fraction * problem.stroke,
            problem.stroke
        ));
    });
    let wall_s = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let mut summary = RunSummary::new(&name, &scene, &result, wall_s);
    write_run(&dir, &mut summary, &result, &problem.tooling)?;
    if args.json {
        println!("{}", summary.to_json());
    } else {
        print!("{}", summary.to_text());
    }
    if !summary.unsound.is_empty() {
        return Err(CliError::failed(format!(
            "{}: the result cannot be trusted: {}",
            args.scene.display(),
            summary.unsound.join("; ")
        )));
    }
    if !result.converged {
        let no_answer = matches!(result.failure, Some(DrawingFailure::NoUniqueShape(_)));
        let what = if no_answer {
            "the drawing has no answer"
        } else {
            "the drawing did not converge"
        };
        return Err(CliError::failed(format!(
            "{}: {what}: {}",
            args.scene.display(),
            result
                .failure
                .as_ref()
                .map_or("no cause given".to_string(), |f| f.to_string())
        )));
    }
    Ok(())
}
