//! `wovenform tools SCENE.toml --out DIR [--spacing MM]`: the scene's punch and die as closed
//! triangle surfaces, written as binary STL (punch.stl, die.stl).

use std::path::{Path, PathBuf};

use clap::Args;

use super::CliError;
use super::outputs;
use super::scene_args::SceneFileArgs;
use wovenform::core::tools::surface::TriSurface;
use wovenform::study::tessellation::{check_spacing, tessellate};

#[derive(Args, Debug)]
pub struct ToolsArgs {
    #[command(flatten)]
    pub scene: SceneFileArgs,
    /// Output folder (created if missing) for punch.stl and die.stl.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Grid spacing of the tessellation, mm: triangles about this size (their count grows as
    /// 1/spacing²).
    #[arg(long, value_name = "MM", default_value_t = 1.0)]
    pub spacing: f64,
}

pub fn exec(args: ToolsArgs) -> Result<(), CliError> {
    let file = &args.scene.scene;
    let scene = args.scene.load()?;
    check_spacing(&scene, args.spacing).map_err(|e| CliError::bad_input(e.to_string()))?;
    let files = outputs::in_dir(&args.out, &["punch.stl", "die.stl"]);
    let inputs = outputs::scene_inputs(Some(file), &scene);
    outputs::prepare(&args.out, &files, &inputs)?;
    let surfaces = tessellate(&scene, args.spacing);
    for (i, (name, surface)) in surfaces.tools.iter().enumerate() {
        let path = args.out.join(format!("{name}.stl"));
        write(&path, surface, file)?;
        let from = match &surfaces.read_from {
            Some(files) => format!("as read from {}", files[i]),
            None => format!("spacing {} mm", args.spacing),
        };
        let count = surface.triangles.len();
        println!("{}: {count} triangles ({from})", path.display());
    }
    if surfaces.read_from.is_none() {
        eprintln!("tessellated in {:.2} s", surfaces.wall_s);
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
