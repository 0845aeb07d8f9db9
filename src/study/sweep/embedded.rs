//! Sweeps whose base scene may be one the binary carries ([`crate::presets`]): the
//! explorer's default sweep, which reads nothing from the disk.

use std::path::Path;

use super::{Plan, SweepError};
use crate::presets::{EXPLORER_NAME, SCENES, explorer_document};

/// The plan of a sweep document whose `base` may be a scene the binary carries.
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
