//! wovenform: finite-element simulation of woven-fabric deep drawing (the seed paper's method)
//! and a design-space explorer around it.
//!
//! # Layout and data flow
//!
//! Data flows one way, and each layer only uses the ones before it:
//!
//! ```text
//! scene ──► core ──► study ──► report ──► publish / cli / tui
//! (input)  (numerics) (drives the core)  (draws, formats)  (files, terminal, a person)
//! ```
//!
//! - [`core`]: pure numerics (the woven-cell law, the membrane element, the Newton solver, the
//!   tools and their contact, the drawing problem). No files, no terminal, no serde, no clock.
//! - [`scene`]: the TOML scene a user writes, checked against physical bounds, turned into a
//!   [`core::drawing::DrawingProblem`]. [`presets`] are the scenes the binary carries.
//! - [`summary`], [`verdict`], [`accuracy`]: what one run came to, the one feasibility rule, and
//!   the error each accuracy level carries. [`machine`]: what this machine can hold.
//! - [`study`]: the studies that drive the core — a sweep of designs (its plan, grid, rows,
//!   output folder, parallel run and merge), the convergence study, the law's fit, the benchmark.
//! - [`report`]: pictures and text made from plain data; it reads no file.
//! - [`publish`]: writes what `report` draws into a run's or a sweep's folder.
//! - [`tui`]: the terminal explorer; the command line (`src/cli/`) lives in the binary.
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
