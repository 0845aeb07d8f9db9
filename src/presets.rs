//! The presets the binary carries, so that it works from any folder: the paper's box scenes
//! and the explorer's default sweep (`presets/paper-box-explorer.toml` over
//! `presets/paper-box-open.toml`).

use std::path::Path;

use crate::study::sweep::{Plan, SweepError};

/// `presets/paper-box-open.toml`: the paper's square box with the open radii 10/15/10 mm.
pub const PAPER_BOX_OPEN: &str = include_str!("../presets/paper-box-open.toml");
/// `presets/paper-box-tight.toml`: the paper's square box with the tight radii 5/6/5 mm.
pub const PAPER_BOX_TIGHT: &str = include_str!("../presets/paper-box-tight.toml");
/// `presets/paper-box-explorer.toml`: the explorer's default sweep (8 designs).
pub const PAPER_BOX_EXPLORER: &str = include_str!("../presets/paper-box-explorer.toml");

/// The scene files an embedded sweep may name as its `base`.
const SCENES: [(&str, &str); 2] = [
    ("paper-box-open.toml", PAPER_BOX_OPEN),
    ("paper-box-tight.toml", PAPER_BOX_TIGHT),
];

/// What the explorer's default sweep is called: the path its errors name and the sweep's name
/// (its export folder is `paper-box-explorer-export`).
pub const EXPLORER_NAME: &str = "paper-box-explorer";

/// The explorer's default sweep as a sweep document; its `base` is one of `SCENES`, which
/// [`plan`] reads from the binary, nothing from the disk.
pub fn explorer_document() -> toml::Table {
    let doc: toml::Table = PAPER_BOX_EXPLORER
        .parse()
        .expect("the embedded sweep preset is valid TOML");
    let base = doc.get("base").and_then(toml::Value::as_str);
    assert!(
        SCENES.iter().any(|(name, _)| Some(*name) == base),
        "the embedded sweep preset's base is an embedded scene"
    );
    doc
}

/// The plan of a sweep document whose `base` may be a scene the binary carries (`SCENES`).
pub fn plan(path: &Path, doc: &toml::Table, sets: &[String]) -> Result<Plan, SweepError> {
    Plan::from_document_with(path, doc, sets, &SCENES)
}

/// The plan of the explorer's default sweep with `sets` (`KEY=VALUE`) over its base scene.
pub fn explorer_sweep(sets: &[String]) -> Result<Plan, SweepError> {
    plan(Path::new(EXPLORER_NAME), &explorer_document(), sets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_default_is_the_preset_file_and_the_paper_designs() {
        let embedded = explorer_sweep(&[]).unwrap();
        assert_eq!(embedded.len(), 8);
        assert_eq!(embedded.name(), "paper-box-explorer");
        // The file as `wovenform sweep` reads it, its base from the disk: the same grid.
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/paper-box-explorer.toml");
        let read = Plan::load(&file, &[]).unwrap();
        assert_eq!(read.designs(), embedded.designs());
        assert_eq!(read.base_scene, embedded.base_scene);
        assert_eq!(read.base_hash, embedded.base_hash);
        assert_eq!(read.sweep_hash, embedded.sweep_hash);
        // Both of the paper's designs, (r, rp, rm) = (5, 6, 5) and (10, 15, 10), at μ 0.2.
        let radii: Vec<Vec<f64>> = embedded
            .designs()
            .iter()
            .map(|d| {
                let s = embedded.design_scene(d).unwrap();
                assert_eq!(s.process.friction, 0.2);
                vec![s.tools.r, s.tools.rp, s.tools.rm]
            })
            .collect();
        assert!(radii.contains(&vec![5.0, 6.0, 5.0]));
        assert!(radii.contains(&vec![10.0, 15.0, 10.0]));
    }
}
