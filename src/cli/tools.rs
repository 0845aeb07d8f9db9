//! `wovenform tools SCENE.toml --out DIR [--spacing MM]`: the scene's punch and die as closed
//! triangle surfaces, written as binary STL (punch.stl, die.stl).

use std::path::{Path, PathBuf};

use clap::Args;

use super::CliError;
use super::outputs::{self, STL_HEAD};
use super::scene_args::SceneArgs;
use wovenform::core::drawing::Tooling;
use wovenform::core::tools::capped::{grid_points, tool_surfaces};
use wovenform::core::tools::surface::TriSurface;
use wovenform::files::Output;
use wovenform::machine::memory_budget_bytes;

/// Memory per grid point while tessellating, bytes (its field value, its cell's vertex index,
/// and the surface built on it).
const BYTES_PER_GRID_POINT: f64 = 16.0;

#[derive(Args, Debug)]
pub struct ToolsArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub scene: PathBuf,
    /// Override one scene key; VALUE is a TOML literal, e.g. --set tools.rm=8 or
    /// --set process.stroke=30. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output folder (created if missing) for punch.stl and die.stl.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Grid spacing of the tessellation, mm: triangles about this size (their count grows as
    /// 1/spacing²).
    #[arg(long, value_name = "MM", default_value_t = 1.0)]
    pub spacing: f64,
}

pub fn exec(args: ToolsArgs) -> Result<(), CliError> {
    let scene = SceneArgs {
        scene: Some(args.scene.clone()),
        set: args.set.clone(),
    }
    .load()?;
    let problem = scene.to_problem();
    let files = ["punch.stl", "die.stl"].map(|n| Output::owned_if(args.out.join(n), STL_HEAD));
    let inputs = outputs::scene_inputs(Some(&args.scene), &scene);
    if let Tooling::Mesh { punch, die } = &problem.tooling {
        // Tools read from STL are written back as read.
        outputs::prepare(&args.out, &files, &inputs)?;
        for (name, tool) in [("punch", punch), ("die", die)] {
            let path = args.out.join(format!("{name}.stl"));
            let surface = tool.surface();
            write(&path, &surface, &args.scene)?;
            println!(
                "{}: {} triangles (as read from {})",
                path.display(),
                surface.triangles.len(),
                tool.name
            );
        }
        return Ok(());
    }
    check_spacing(
        args.spacing,
        scene.tools.smallest_radius_mm(),
        grid_points(
            &problem.tooling,
            problem.blank,
            problem.stroke,
            args.spacing,
        ),
    )?;
    outputs::prepare(&args.out, &files, &inputs)?;
    let start = std::time::Instant::now();
    let (punch, die) = tool_surfaces(
        &problem.tooling,
        problem.blank,
        problem.stroke,
        args.spacing,
    );
    let wall_s = start.elapsed().as_secs_f64();
    for (name, surface) in [("punch", &punch), ("die", &die)] {
        let path = args.out.join(format!("{name}.stl"));
        write(&path, surface, &args.scene)?;
        println!(
            "{}: {} triangles (spacing {} mm)",
            path.display(),
            surface.triangles.len(),
            args.spacing
        );
    }
    eprintln!("tessellated in {wall_s:.2} s");
    Ok(())
}

/// Refuses a spacing that is not a positive length, that is coarser than the tools' smallest
/// radius (the shape would be lost), or whose grid does not fit in memory.
fn check_spacing(spacing: f64, smallest_radius: f64, points: f64) -> Result<(), CliError> {
    if !(spacing.is_finite() && spacing > 0.0) {
        return Err(CliError::bad_input(format!(
            "--spacing {spacing}: expected a positive length in mm"
        )));
    }
    if spacing > smallest_radius {
        return Err(CliError::bad_input(format!(
            "--spacing {spacing} mm is coarser than the tools' smallest radius \
             ({smallest_radius} mm): expected at most {smallest_radius} mm"
        )));
    }
    let (bytes, budget) = (BYTES_PER_GRID_POINT * points, memory_budget_bytes());
    if bytes > budget {
        // The grid's points fall as 1/spacing³.
        let fits = spacing * (bytes / budget).cbrt() * 1.01;
        return Err(CliError::bad_input(format!(
            "--spacing {spacing} mm needs {points:.3e} grid points ({:.1} GB), over this \
             machine's {:.1} GB: expected --spacing ≥ {fits:.3} mm",
            bytes / 1e9,
            budget / 1e9
        )));
    }
    Ok(())
}

/// Writes one tool, checked first (a surface that fails is a fault of the tessellation).
fn write(path: &Path, surface: &TriSurface, scene: &Path) -> Result<(), CliError> {
    surface.check().map_err(|e| {
        CliError::failed(format!(
            "{}: the tessellated tool is not a closed surface: {e}",
            scene.display()
        ))
    })?;
    wovenform::stl::write_binary(path, surface).map_err(|e| CliError::bad_input(e.to_string()))
}
