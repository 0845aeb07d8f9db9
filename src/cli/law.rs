//! `wovenform law`: the biaxial woven-cell law at one strain pair (one JSON object), or the
//! paper's Figure 6 with `--curves`.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use super::scene_args::SceneArgs;
use super::{CliError, outputs};
use wovenform::core::fabric::law::CellLaw;
use wovenform::publish::write_figure6;
use wovenform::study::fit::STRAIN_RANGE;

#[derive(Args, Debug)]
pub struct LawArgs {
    /// Warp strain ε11 (in [-0.05, 0.10]).
    #[arg(
        long,
        allow_negative_numbers = true,
        required_unless_present = "curves"
    )]
    pub eps1: Option<f64>,
    /// Weft strain ε22 (in [-0.05, 0.10]).
    #[arg(
        long,
        allow_negative_numbers = true,
        required_unless_present = "curves"
    )]
    pub eps2: Option<f64>,
    /// Write the paper's Figure 6 (figure6.csv, figure6.png) into --out instead.
    #[arg(long, conflicts_with_all = ["eps1", "eps2"], requires = "out")]
    pub curves: bool,
    /// Output folder for --curves.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub scene: SceneArgs,
}

/// The fields printed by `wovenform law` (N, mm).
#[derive(Serialize)]
struct LawOutput {
    t11: f64,
    t22: f64,
    w1: f64,
    w2: f64,
    closure: f64,
    dt11_de1: f64,
    dt11_de2: f64,
    dt22_de1: f64,
    dt22_de2: f64,
}

fn strain(name: &str, v: Option<f64>) -> Result<f64, CliError> {
    let v = v.expect("clap requires --eps1 and --eps2 without --curves");
    if (STRAIN_RANGE[0]..=STRAIN_RANGE[1]).contains(&v) {
        Ok(v)
    } else {
        Err(CliError::bad_input(format!(
            "--{name} = {v}: expected a strain in [{:.2}, {:.2}]",
            STRAIN_RANGE[0], STRAIN_RANGE[1]
        )))
    }
}

pub fn exec(args: LawArgs) -> Result<(), CliError> {
    let scene = args.scene.load()?;
    let params = scene.to_cell_params();
    if args.curves {
        let out = args
            .out
            .as_deref()
            .expect("clap requires --out with --curves");
        let files = outputs::in_dir(out, &["figure6.png", "figure6.csv"]);
        let inputs = outputs::scene_inputs(args.scene.scene.as_deref(), &scene);
        outputs::prepare(out, &files, &inputs)?;
        let written = write_figure6(params, out)?;
        for path in written {
            println!("{}", path.display());
        }
        return Ok(());
    }
    let eps = [strain("eps1", args.eps1)?, strain("eps2", args.eps2)?];
    let law = CellLaw::new(params);
    let r = law.evaluate(eps, law.initial_state());
    let w = r.w(&law);
    let out = LawOutput {
        t11: r.t[0],
        t22: r.t[1],
        w1: w[0],
        w2: w[1],
        closure: r.crimp.s,
        dt11_de1: r.dt[0][0],
        dt11_de2: r.dt[0][1],
        dt22_de1: r.dt[1][0],
        dt22_de2: r.dt[1][1],
    };
    println!("{}", serde_json::to_string(&out).expect("plain numbers"));
    Ok(())
}
