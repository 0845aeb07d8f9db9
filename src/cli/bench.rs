//! `wovenform bench`: throughput on this machine (one thread; medians of several repetitions).

use clap::Args;

use super::CliError;
use wovenform::study::bench as b;

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Repetitions per measurement (the median is reported), 1 to 99.
    #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u16).range(1..100))]
    pub repetitions: u16,
    /// Also compare ways of resolving friction within a load step (implicit with the exact or
    /// the symmetric Jacobian, lagged, lagged to a fixed point) on the open box.
    #[arg(long)]
    pub friction: bool,
    /// Also time tools read from STL (~100 000 triangles each) against the same analytic
    /// tools: the open and tight box and the hemisphere, whole blank.
    #[arg(long)]
    pub mesh: bool,
    /// Also measure what a finer answer costs: five designs of the paper's grid at fine over
    /// standard, the long bias-extension specimen over the short one, the open box at fine on
    /// one thread and on all (each run stopped after --deadline seconds; minutes in all).
    #[arg(long)]
    pub scaling: bool,
    /// Also time the open box (whole blank, standard) with bending against the same box
    /// without it: what bending costs at the same mesh (about 20 s).
    #[arg(long)]
    pub bending: bool,
    /// With --scaling: stop each run after this many seconds (a ratio is then a lower bound).
    #[arg(long, default_value_t = 600.0, value_name = "S")]
    pub deadline: f64,
}

/// `wovenform bench`: law and element throughput, one thread.
pub fn exec(args: BenchArgs) -> Result<(), CliError> {
    if !(args.deadline.is_finite() && args.deadline > 0.0) {
        return Err(CliError::bad_input(format!(
            "--deadline {}: expected a number of seconds above 0",
            args.deadline
        )));
    }
    let options = b::BenchOptions {
        repetitions: usize::from(args.repetitions),
        friction: args.friction,
        mesh: args.mesh,
        scaling: args.scaling.then_some(args.deadline),
        bending: args.bending,
    };
    let note = |what: &str| {
        if !args.json {
            eprintln!("measuring {what} …");
        }
    };
    let measured = b::measure_all(&options, &note).map_err(|e| CliError::failed(e.to_string()))?;
    if args.json {
        println!("{}", measured.to_json());
    } else {
        print!("{}", measured.to_text());
    }
    Ok(())
}
