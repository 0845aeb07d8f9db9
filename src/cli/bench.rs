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
}

/// `wovenform bench`: law and element throughput, one thread.
pub fn exec(args: BenchArgs) -> Result<(), CliError> {
    let options = b::BenchOptions {
        repetitions: usize::from(args.repetitions),
        friction: args.friction,
        mesh: args.mesh,
    };
    let note = |what: &str| {
        if !args.json {
            eprintln!("measuring {what} …");
        }
    };
    let measured = b::measure_all(&options, &note).map_err(CliError::failed)?;
    if args.json {
        println!("{}", measured.to_json());
    } else {
        print!("{}", measured.to_text());
    }
    Ok(())
}
