//! wovenform: finite-element simulation of woven-fabric deep drawing (the seed paper's method)
//! and a design-space explorer around it.
//!
//! # Layout and data flow
//!
//! Data flows one way:
//!
//! ```text
//! scene ──► core ──► study ──► report ──► publish / cli / tui
//! (input)  (numerics) (drives the core)  (draws, formats)  (files, terminal, a person)
//! ```
//!
//! and each module below uses only the modules listed before it:
//!
//! 1. [`core`]: pure numerics (the woven-cell law, the membrane element, the Newton solver, the
//!    tools and their contact, the drawing problem). No files, no terminal, no serde, no clock.
//! 2. [`files`]: writing files whole and never over a command's inputs.
//!    [`machine`]: what this machine can hold (its memory), asked before a mesh is allocated.
//!    [`stl`]: tool surfaces ([`core::tools::surface::TriSurface`]) read from and written to
//!    STL files, with the refusals of a file that cannot be a tool.
//! 3. [`scene`]: the TOML scene a user writes, checked against physical bounds (and against
//!    the machine), turned into a [`core::drawing::DrawingProblem`].
//! 4. [`accuracy`], [`verdict`], [`summary`]: the error each accuracy level carries, the one
//!    feasibility rule, what one run came to.
//! 5. [`study`]: the studies that drive the core — a sweep of designs (its plan, grid, rows,
//!    output folder with its lock and resume, parallel run and merge), the convergence study,
//!    the law's fit, the benchmark. A sweep keeps its rows and fields in its folder as it goes,
//!    so that an interrupted sweep loses nothing.
//! 6. [`presets`]: the scenes and the explorer's sweep that the binary carries.
//! 7. [`report`]: pictures and text made from plain data; it reads no file (it writes the
//!    PNGs it draws).
//! 8. [`publish`]: writes what `report` makes into a run's or a sweep's folder.
//! 9. [`tui`]: the terminal explorer. The command line (`src/cli/`) lives in the binary.
pub mod accuracy;
pub mod core;
pub mod files;
pub mod guide;
pub mod machine;
pub mod presets;
pub mod publish;
pub mod report;
pub mod scene;
pub mod stl;
pub mod study;
pub mod summary;
pub mod tui;
pub mod verdict;
