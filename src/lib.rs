//! wovenform: finite-element simulation of woven-fabric deep drawing (the method of Boisse
//! et al., 1997) and a design-space explorer around it.
//!
//! Data flows one way: scene → core → study → report → publish / cli / tui. The layers, what
//! each may use, the invariants and the map of every file are in
//! [`guide::architecture`]; the rest of the [`guide`] explains each task (scenes, the
//! explorer, sweeps, STL tools, the shear law, accuracy), the theory, the verification and
//! the measured findings. `cargo doc --open` renders it.
pub mod accuracy;
pub mod core;
pub mod files;
pub mod guide;
pub mod machine;
pub mod presets;
pub mod publish;
pub mod report;
pub mod scene;
pub mod show;
pub mod stl;
pub mod study;
pub mod summary;
pub mod tui;
pub mod verdict;
