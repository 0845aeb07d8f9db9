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
    let reps = usize::from(args.repetitions);
    let note = |what: &str| {
        if !args.json {
            eprintln!("measuring {what} …");
        }
    };
    note("the law and the element");
    let rates = [b::law_rate(reps), b::element_rate(reps)];
    let box_reps = reps.min(5);
    let mut drawings = Vec::new();
    for (name, problem) in b::cases() {
        note(&format!("the {name} at standard accuracy"));
        let run = b::drawing_run(&problem, box_reps)
            .map_err(|e| CliError::failed(format!("{name}: {e}")))?;
        drawings.push((name, run));
    }
    note("wall time against dofs (5, 3.5, 2.5, 1.75 mm)");
    let (ladder, exponent) = b::dof_scaling(&[5.0, 3.5, 2.5, 1.75]);
    note("sweep throughput with 1 and 2 jobs");
    let one = b::sweep_throughput(1).map_err(CliError::failed)?;
    let two = b::sweep_throughput(2).map_err(CliError::failed)?;
    let friction = if args.friction {
        note("friction resolved within the step against lagged, on the open box");
        b::friction_resolution(box_reps.min(3))
    } else {
        Vec::new()
    };
    let mesh = if args.mesh {
        note("STL tools against the analytic ones (open box, tight box, hemisphere)");
        wovenform::study::mesh_bench::mesh_tools(box_reps.min(3))
    } else {
        Vec::new()
    };
    let report = wovenform::report::bench::BenchReport {
        reps,
        box_reps,
        rates,
        drawings,
        ladder,
        exponent,
        sweep_per_min: [one, two],
        friction,
        mesh,
    };
    if args.json {
        println!("{}", report.to_json());
    } else {
        print!("{}", report.to_text());
    }
    Ok(())
}
