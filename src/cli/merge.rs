//! `wovenform merge DIR... --out DIR`: the shards of one sweep into one results set.

use std::path::PathBuf;

use clap::Args;

use super::CliError;
use super::sweep::print_outcome;
use wovenform::publish;
use wovenform::study::sweep;

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The output folders of the shards (of one sweep).
    #[arg(value_name = "DIR", required = true)]
    pub dirs: Vec<PathBuf>,
    /// Output folder for the combined results (one that holds an earlier merge of this sweep
    /// keeps its rows and gets the designs it lacks).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Maps drawn at once (default: every core).
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
}

pub fn exec(args: MergeArgs) -> Result<(), CliError> {
    let start = std::time::Instant::now();
    let pool = sweep::pool(args.jobs)?;
    let (plan, mut outcome) = sweep::merge(&args.dirs, &args.out)?;
    outcome.files = publish::sweep_report(&plan, &args.out, &outcome.rows, None, &pool)?;
    outcome.wall_s = start.elapsed().as_secs_f64();
    eprintln!(
        "merged {} folders: {}",
        args.dirs.len(),
        outcome.kept.describe()
    );
    print_outcome(&plan, &outcome);
    Ok(())
}
