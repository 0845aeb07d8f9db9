//! The options the subcommands share, declared once and flattened into each: the scene file
//! with its `--set` overrides, the accuracy level and an optional output folder.

use std::path::{Path, PathBuf};

use clap::Args;

use super::CliError;
use wovenform::accuracy::{Accuracy, UnknownAccuracy};
use wovenform::scene::{Override, Scene};

/// `--set KEY=VALUE`, repeatable.
#[derive(Args, Debug, Clone, Default)]
pub struct SetArgs {
    /// Override one scene key (of a sweep: of its base scene); VALUE is a TOML literal, e.g.
    /// --set tools.r=7.5 or --set blank.size=[130,100]. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// `--accuracy LEVEL`.
#[derive(Args, Debug, Clone, Copy, Default)]
pub struct AccuracyArgs {
    /// Accuracy level: coarse (5 mm elements), standard (2.5 mm) or fine (1.25 mm); sets
    /// mesh.element_size (a --set of it wins) and reports the level's measured error.
    #[arg(long, value_name = "LEVEL", value_parser = parse_accuracy)]
    pub accuracy: Option<Accuracy>,
}

impl AccuracyArgs {
    /// The level's overrides, then the user's own (which win).
    pub fn with(&self, set: &SetArgs) -> Vec<String> {
        let mut all = self.accuracy.map(|a| a.overrides()).unwrap_or_default();
        all.extend_from_slice(&set.set);
        all
    }
}

/// `--out DIR`, with a default folder under `out/`.
#[derive(Args, Debug, Clone, Default)]
pub struct OutArgs {
    /// Output folder (default: under out/, named after the input file: out/NAME for run,
    /// out/bias-NAME, out/fit-NAME, out/fit-bias-NAME).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

impl OutArgs {
    /// The folder given, else `out/<prefix><stem of file>`.
    pub fn dir(&self, prefix: &str, file: &Path) -> PathBuf {
        self.out
            .clone()
            .unwrap_or_else(|| super::outputs::default_dir(prefix, file))
    }
}

/// The grid a sweep, a frontier and a Slurm job array run: the sweep file with its `--set`
/// overrides of the base scene and the accuracy level.
#[derive(Args, Debug, Clone)]
pub struct GridArgs {
    /// Sweep file (TOML): a base scene and a [sweep] table of parameters (for a frontier, its
    /// axis's values give the range searched and, by their count, the resolution: one step of
    /// that grid).
    #[arg(value_name = "SWEEP.toml")]
    pub sweep: PathBuf,
    // `--set` is passed on to every run (and every Slurm task).
    #[command(flatten)]
    pub set: SetArgs,
    #[command(flatten)]
    pub accuracy: AccuracyArgs,
}

impl GridArgs {
    /// The plan of the sweep file with the level's and the user's overrides.
    pub fn plan(&self) -> Result<wovenform::study::sweep::Plan, CliError> {
        let sets = self.accuracy.with(&self.set);
        Ok(wovenform::study::sweep::Plan::load(&self.sweep, &sets)?)
    }
}

/// A scene file given as the command's argument, with its overrides.
#[derive(Args, Debug, Clone)]
pub struct SceneFileArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub scene: PathBuf,
    #[command(flatten)]
    pub set: SetArgs,
}

impl SceneFileArgs {
    /// The scene with the overrides `set` (an accuracy level's, then the user's).
    pub fn load_with(&self, set: &[String]) -> Result<Scene, CliError> {
        load(Some(&self.scene), set)
    }

    /// The scene with the user's overrides.
    pub fn load(&self) -> Result<Scene, CliError> {
        self.load_with(&self.set.set)
    }
}

/// The scene options of `law` and `fit`: a scene file or the embedded default.
#[derive(Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Scene file (TOML); without it, the embedded default (the paper's glass fabric).
    #[arg(long, value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub set: SetArgs,
}

impl SceneArgs {
    /// The scene file (or the default) with the overrides, checked against its bounds.
    pub fn load(&self) -> Result<Scene, CliError> {
        load(self.scene.as_deref(), &self.set.set)
    }
}

/// The scene file (or the default) with the overrides `set`, checked against its bounds.
fn load(file: Option<&Path>, set: &[String]) -> Result<Scene, CliError> {
    let overrides = set
        .iter()
        .map(|s| s.parse::<Override>())
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Scene::load(file, &overrides)?)
}

/// Parses `--accuracy LEVEL`.
pub fn parse_accuracy(text: &str) -> Result<Accuracy, UnknownAccuracy> {
    Accuracy::parse(text)
}
