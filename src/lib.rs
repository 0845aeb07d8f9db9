//! wovenform: finite-element simulation of woven-fabric deep drawing (the seed paper's method)
//! and a design-space explorer around it.
pub mod accuracy;
pub mod core;
pub mod machine;
pub mod presets;
pub mod publish;
pub mod report;
pub mod scene;
pub mod study;
pub mod summary;
pub mod tui;
pub mod verdict;
