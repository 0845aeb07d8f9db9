//! What the subcommands that read a scene share: the scene file, `--set` overrides and the
//! accuracy level.

use std::path::PathBuf;

use clap::Args;

use super::CliError;
use wovenform::accuracy::Accuracy;
use wovenform::scene::{Override, Scene};

/// The scene options of `law` and `fit`.
#[derive(Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Scene file (TOML); without it, the embedded default (the paper's glass fabric).
    #[arg(long, value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    /// Override one scene key; VALUE is a TOML literal, e.g. --set fabric.a=0.05 or
    /// --set fabric.l0=[5.0,4.0]. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

impl SceneArgs {
    /// The scene file (or the default) with the overrides, checked against its bounds.
    pub fn load(&self) -> Result<Scene, CliError> {
        let overrides = self
            .set
            .iter()
            .map(|s| s.parse::<Override>())
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Scene::load(self.scene.as_deref(), &overrides)?)
    }
}

/// Parses `--accuracy LEVEL`.
pub fn parse_accuracy(text: &str) -> Result<Accuracy, String> {
    Accuracy::parse(text)
}

/// The overrides of an accuracy level, before the user's own (which win).
pub fn with_accuracy(level: Option<Accuracy>, set: &[String]) -> Vec<String> {
    let mut all = level.map(|a| a.overrides()).unwrap_or_default();
    all.extend_from_slice(set);
    all
}
