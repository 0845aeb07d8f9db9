//! `wovenform fit DATA.csv`: identify A and B (and C) from measured biaxial tension curves.

use std::path::PathBuf;

use clap::Args;

use super::scene_args::{OutArgs, SceneArgs};
use super::{CliError, outputs};
use wovenform::files::Input;
use wovenform::publish;
use wovenform::study::fit::{self as fitting, FitOptions, FitResult};

#[derive(Args, Debug)]
pub struct FitArgs {
    /// Measured curves: CSV with header eps1,eps2,t11_n,t22_n (strains, tensions per yarn in
    /// N; what `law --curves` writes).
    #[arg(value_name = "DATA.csv")]
    pub data: PathBuf,
    /// Also identify the yarn stiffness C (one value for both yarns).
    #[arg(long)]
    pub fit_c: bool,
    #[command(flatten)]
    pub out: OutArgs,
    /// Fit the shear law to a bias-extension curve instead (DATA.csv with header
    /// displacement_mm,force_n) of a specimen H mm long and W mm wide, e.g. 230x115; writes
    /// fabric.toml, bias.csv, bias.png and shear.png into --out.
    #[arg(long, value_name = "HxW", value_parser = super::fit_bias::parse_specimen)]
    pub bias: Option<[f64; 2]>,
    /// With --bias: the points fitted, up to this ideal central shear, degrees (default: the
    /// scene's locking angle).
    #[arg(long, value_name = "DEG")]
    pub max_shear: Option<f64>,
    /// With --bias: the points fitted from this grip displacement on, mm (a measured curve's
    /// initial rise is a moment at zero shear that the polynomial does not have).
    #[arg(long = "from", default_value_t = 3.0, value_name = "MM")]
    pub from_mm: f64,
    /// With --bias: refining passes on the finite-element test.
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub refine: usize,
    /// With --bias: element size of the finite-element test, mm.
    #[arg(long, default_value_t = 5.0, value_name = "MM")]
    pub element_size: f64,
    #[command(flatten)]
    pub scene: SceneArgs,
}

pub fn exec(args: FitArgs) -> Result<(), CliError> {
    let scene = args.scene.load()?;
    if let Some(specimen) = args.bias {
        return super::fit_bias::exec(&scene, bias_fit_args(&args, specimen));
    }
    let samples =
        fitting::read_samples(&args.data).map_err(|e| CliError::bad_input(e.to_string()))?;
    let dir = args.out.dir("fit-", &args.data);
    let mut inputs = outputs::scene_inputs(args.scene.scene.as_deref(), &scene);
    inputs.push(Input::new(&args.data, "the measured curves"));
    outputs::prepare(&dir, &outputs::in_dir(&dir, &["fit.png"]), &inputs)?;
    let options = FitOptions {
        fit_c: args.fit_c,
        ..FitOptions::default()
    };
    let result = fitting::fit(&samples, scene.to_cell_params(), options).map_err(|e| {
        let message = format!("{}: {e}", args.data.display());
        match e {
            // The data and the scene were fine; the iterations were not.
            fitting::FitError::Diverged => CliError::failed(message),
            _ => CliError::bad_input(message),
        }
    })?;
    print_result(&args, &result);
    let name = args.data.file_name().unwrap_or(args.data.as_os_str());
    let png = publish::write_fit(&dir, &samples, &result, &name.to_string_lossy())?;
    println!("{}", png.display());
    if !result.converged {
        return Err(CliError::failed(format!(
            "the fit did not converge in {} iterations; the values above are the last iterate",
            result.iterations
        )));
    }
    Ok(())
}

/// The fitted values with their uncertainty and flags, the residual and the iterations; a
/// warning on stderr for each parameter the data do not pin.
fn print_result(args: &FitArgs, result: &FitResult) {
    let p = result.params;
    let spread = |name: &str| {
        let check = result.checks.iter().find(|c| c.name == name);
        check.map_or(String::new(), |c| {
            let flag = if c.at_bound.is_some() {
                ", on its bound"
            } else if c.unidentified() {
                ", not identified"
            } else {
                ""
            };
            format!(" (± {}{flag})", fitting::percent(c.rel_uncertainty))
        })
    };
    println!("fit of {}", args.data.display());
    println!("A = {:.6} mm{}", p.a, spread("A"));
    println!("B = {:.6} 1/N{}", p.b, spread("B"));
    let c_note = if args.fit_c {
        spread("C")
    } else {
        " (fixed)".into()
    };
    if p.c[0] == p.c[1] {
        println!("C = {:.1} N{c_note}", p.c[0]);
    } else {
        println!("C = [{:.1}, {:.1}] N{c_note}", p.c[0], p.c[1]);
    }
    for warning in result.checks.iter().filter_map(|c| c.warning()) {
        eprintln!("warning: {}: {warning}", args.data.display());
    }
    println!("RMS residual = {:.4} N", result.rms_n);
    println!("points = {}", result.points);
    println!("iterations = {}", result.iterations);
}

/// What `fit --bias HxW` (the specimen's sides) was given.
fn bias_fit_args(args: &FitArgs, specimen: [f64; 2]) -> super::fit_bias::BiasFitArgs<'_> {
    super::fit_bias::BiasFitArgs {
        data: &args.data,
        specimen,
        max_shear_deg: args.max_shear,
        from_mm: args.from_mm,
        refine: args.refine,
        element_size: args.element_size,
        out: args.out.out.clone(),
        scene_file: args.scene.scene.clone(),
    }
}
