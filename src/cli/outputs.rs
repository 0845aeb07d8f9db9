//! A command's output folder, made ready before any work: created, writable, and none of the
//! files it will write is one of the command's inputs or a user's own file
//! ([`wovenform::files::check_outputs`]). Refusals are bad input (exit 2).

use std::path::{Path, PathBuf};

use super::CliError;
use wovenform::files::{Input, Output, check_outputs};
use wovenform::scene::Scene;
use wovenform::scene::ToolKind;

/// The first bytes of the CSV curve that `bias` and `fit --bias` write.
pub const BIAS_CSV_HEAD: &[u8] = b"displacement_mm,force_n,shear_centre_deg\n";
/// The first bytes of the `fabric.toml` that `fit --bias` writes.
pub const FABRIC_TOML_HEAD: &[u8] = b"# The fabric of ";
/// The first bytes of the `summary.json` that `run` writes.
pub const SUMMARY_JSON_HEAD: &[u8] = b"{\n  \"scene\": ";
/// The first bytes of `figure6.csv` (`law --curves`).
pub const FIGURE6_CSV_HEAD: &[u8] = b"k,eps1,eps2,";
/// The first bytes of `converge.csv`.
pub const CONVERGE_CSV_HEAD: &[u8] = b"ladder,element_size_mm,";
/// The first bytes of every binary STL that wovenform writes.
pub const STL_HEAD: &[u8] = b"binary STL written by wovenform";

/// The files a scene brings in: the scene file (when there is one) and a mesh scene's STL
/// tools (as loaded: absolute paths).
pub fn scene_inputs(file: Option<&Path>, scene: &Scene) -> Vec<Input> {
    let mut inputs: Vec<Input> = file
        .map(|f| Input::new(f, "the scene file"))
        .into_iter()
        .collect();
    if scene.tools.kind == ToolKind::Mesh {
        inputs.push(Input::new(
            &scene.tools.punch,
            "the punch's STL, tools.punch,",
        ));
        inputs.push(Input::new(&scene.tools.die, "the die's STL, tools.die,"));
    }
    inputs
}

/// Creates `dir`, checks that a file can be written there, and refuses `outputs` (files in
/// `dir`) that would overwrite an input or a user's file.
pub fn prepare(dir: &Path, outputs: &[Output], inputs: &[Input]) -> Result<(), CliError> {
    check_outputs(outputs, inputs).map_err(|e| CliError::bad_input(e.to_string()))?;
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::bad_input(format!(
            "{}: not a folder: expected an output folder (--out) to write into",
            dir.display()
        )));
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        CliError::bad_input(format!(
            "{}: cannot create the output folder: {e}",
            dir.display()
        ))
    })?;
    tempfile::NamedTempFile::new_in(dir).map_err(|e| {
        CliError::bad_input(format!(
            "{}: cannot write into the output folder: {e}",
            dir.display()
        ))
    })?;
    Ok(())
}

/// `names` in `dir`, each replaceable.
pub fn replaceable(dir: &Path, names: &[&str]) -> Vec<Output> {
    names
        .iter()
        .map(|n| Output::replaceable(dir.join(n)))
        .collect()
}

/// The default output folder `out/<prefix><stem of file>`.
pub fn default_dir(prefix: &str, file: &Path) -> PathBuf {
    Path::new("out").join(format!("{prefix}{}", stem(file, "input")))
}

/// The file's name without its extension (`otherwise` when it has none).
pub fn stem(file: &Path, otherwise: &str) -> String {
    file.file_stem()
        .map_or_else(|| otherwise.into(), |s| s.to_string_lossy().into_owned())
}
