//! The presets the binary carries, so that it works from any folder: the paper's box scenes
//! and the explorer's default sweep (`presets/paper-box-explorer.toml` over
//! `presets/paper-box-open.toml`), as text: plain data that nothing but `toml` is needed to
//! read, so that every layer may use it.

/// `presets/paper-box-open.toml`: the paper's square box with the open radii 10/15/10 mm.
pub const PAPER_BOX_OPEN: &str = include_str!("../presets/paper-box-open.toml");
/// `presets/paper-box-tight.toml`: the paper's square box with the tight radii 5/6/5 mm.
pub const PAPER_BOX_TIGHT: &str = include_str!("../presets/paper-box-tight.toml");
/// `presets/box-with-shear.toml`: the open box in the glass fabric with its fitted shear law
/// (the bias-extension benchmark's fabric, for `bench --scaling`).
pub const BOX_WITH_SHEAR: &str = include_str!("../presets/box-with-shear.toml");
/// `presets/paper-box-explorer.toml`: the explorer's default sweep (8 designs).
pub const PAPER_BOX_EXPLORER: &str = include_str!("../presets/paper-box-explorer.toml");

/// The scene files an embedded sweep may name as its `base`.
pub const SCENES: [(&str, &str); 2] = [
    ("paper-box-open.toml", PAPER_BOX_OPEN),
    ("paper-box-tight.toml", PAPER_BOX_TIGHT),
];

/// What the explorer's default sweep is called: the path its errors name and the sweep's name
/// (its export folder is `paper-box-explorer-export`).
pub const EXPLORER_NAME: &str = "paper-box-explorer";

/// The explorer's default sweep as a sweep document; its `base` is one of [`SCENES`], which
/// its plan ([`crate::study::sweep::embedded`]) reads from the binary, nothing from the disk.
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
