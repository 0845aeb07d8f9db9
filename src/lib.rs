//! wovenform: finite-element simulation of woven-fabric deep drawing (the seed paper's method)
//! and a design-space explorer around it.
pub mod accuracy;
pub mod bench;
pub mod converge;
pub mod core;
pub mod fit;
pub mod machine;
pub mod presets;
pub mod report;
pub mod scene;
pub mod sweep;
pub mod tui;
