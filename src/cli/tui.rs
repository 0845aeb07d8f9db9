//! `wovenform tui [SWEEP.toml]` (and `wovenform` alone): the explorer in a terminal; without a
//! terminal, an overview of the law and a pointer to `--help`.

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::Args;

use super::CliError;
use wovenform::core::fabric::law::{CellLaw, CellParams};
use wovenform::tui;

#[derive(Args, Debug)]
pub struct TuiArgs {
    /// Sweep file (TOML), as for `sweep`; default: the paper's box, tight and open radii.
    #[arg(value_name = "SWEEP.toml")]
    pub sweep: Option<PathBuf>,
}

/// `wovenform` alone: the explorer in a terminal, else the overview.
pub fn exec_default() -> Result<(), CliError> {
    if std::io::stdout().is_terminal() && std::io::stdin().is_terminal() {
        exec(TuiArgs { sweep: None })
    } else {
        overview();
        Ok(())
    }
}

pub fn exec(args: TuiArgs) -> Result<(), CliError> {
    let source = match &args.sweep {
        Some(path) => tui::source_of_file(path).map_err(|e| CliError::bad_input(e.to_string()))?,
        None => tui::params::default_source(),
    };
    let params =
        tui::params::Parameters::new(source).map_err(|e| CliError::bad_input(e.to_string()))?;
    if !std::io::stdout().is_terminal() {
        return Err(CliError::bad_input(
            "the explorer needs a terminal; use `wovenform sweep SWEEP.toml --out DIR` in scripts",
        ));
    }
    let pruned = tui::prune_sessions(&std::env::temp_dir(), 7);
    if pruned > 0 {
        eprintln!(
            "wovenform explorer: removed {pruned} session folder{} older than 7 days from {}",
            wovenform::report::plural(pruned),
            std::env::temp_dir().display()
        );
    }
    let session = tempfile::Builder::new()
        .prefix("wovenform-explorer-")
        .tempdir()
        .map_err(|e| CliError::failed(format!("cannot make the session folder: {e}")))?
        .keep();
    tui::explore(params, session).map_err(|e| {
        let mut error = CliError::failed(e.to_string());
        // Ended by a signal: the shell's convention, 128 + the signal's number.
        if let tui::error::TuiError::Signal(s) = e {
            error.exit_code = u8::try_from(128 + s).unwrap_or(1);
        }
        error
    })
}

/// No subcommand and no terminal: the law at the paper's reference strains and a pointer to
/// --help.
fn overview() {
    let p = CellParams::PAPER_GLASS;
    let law = CellLaw::new(p);
    println!("wovenform: deep drawing of woven fabrics (Boisse et al. 1997)");
    println!(
        "paper glass fabric: L0 = {} mm, e0 = {} mm, C = {} N, A = {} mm, B = {} 1/N",
        p.l0[0], p.e0[0], p.c[0], p.a, p.b
    );
    println!("   ε11     ε22    T11 (N)    T22 (N)  closure (mm)");
    for eps in [[0.004, 0.004], [0.010, 0.0], [0.006, 0.003]] {
        let r = law.evaluate(eps, law.initial_state());
        println!(
            "{:6.3}  {:6.3}  {:9.4}  {:9.4}  {:10.6}",
            eps[0], eps[1], r.t[0], r.t[1], r.crimp.s
        );
    }
    println!();
    println!("draw the paper's box:  wovenform run presets/paper-box-open.toml");
    println!("                       wovenform run presets/paper-box-tight.toml");
    println!("all the commands:      wovenform --help");
}
