//! A command's output folder, made ready before any work: wovenform's own (new, empty or
//! marked as written by wovenform, [`wovenform::files::claim_folder`]), writable, and none of
//! the files it will write is one of the command's inputs
//! ([`wovenform::files::check_outputs`]). Refusals are bad input (exit 2).

use std::path::{Path, PathBuf};

use super::CliError;
use wovenform::files::{Input, check_outputs, claim_folder};
use wovenform::scene::Scene;
use wovenform::scene::ToolKind;

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

/// Refuses `outputs` (files in `dir`) that would overwrite an input, makes `dir` wovenform's
/// output folder ([`claim_folder`]: new, empty or already wovenform's; a folder holding the
/// user's own files is refused) and checks that a file can be written there.
pub fn prepare(dir: &Path, outputs: &[PathBuf], inputs: &[Input]) -> Result<(), CliError> {
    check_outputs(outputs, inputs).map_err(|e| CliError::bad_input(e.to_string()))?;
    claim_folder(dir).map_err(|e| CliError::bad_input(e.to_string()))?;
    tempfile::NamedTempFile::new_in(dir).map_err(|e| {
        CliError::bad_input(format!(
            "{}: cannot write into the output folder: {e}",
            dir.display()
        ))
    })?;
    Ok(())
}

/// `names` in `dir`.
pub fn in_dir(dir: &Path, names: &[&str]) -> Vec<PathBuf> {
    names.iter().map(|n| dir.join(n)).collect()
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
