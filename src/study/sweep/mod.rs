//! Design sweeps: the grid of designs, parallel runs, the results table, resume, shards and
//! merge. What the sweep draws and prints (maps, report sheet, `results.json`, the table) is in
//! [`crate::report::sweep`]; [`crate::publish`] writes it.
//!
//! A sweep file is TOML: a base scene (a scene file relative to the sweep file, and/or an
//! inline `[scene]` table whose keys go over it) and a `[sweep]` table of parameters, each a
//! scene key (`tools.r`, `process.stroke`, ...) or one of the box's short names
//! `r rp rm friction holder_pressure`, with a list of values or a range:
//!
//! ```toml
//! base = "paper-box-open.toml"
//! [scene]
//! mesh.element_size = 3.5
//! [sweep]
//! r = [5.0, 7.5, 10.0]
//! rm = { start = 5.0, stop = 10.0, count = 3 }   # both ends included
//! friction = [0.15, 0.2, 0.25]
//! ```
//!
//! The grid is the Cartesian product of the parameters, in a fixed order whatever the order
//! of the file: the short names first (`r rp rm friction holder_pressure`), then the other keys
//! alphabetically; the last one varies fastest. Design `i` has the id `d007-3fa1c2`: its
//! index and a hash of its parameter values. A design that breaks a bound of the scene
//! (checked by [`crate::scene::Scene::from_toml_str`] with the design's values as overrides) is a row with
//! verdict `INVALID` and the reason; it is not run.
//!
//! Output folder `DIR`: `results.csv` (a row appended and flushed as each design finishes),
//! `fields/<id>.json` (each design's shear field, written before its row), `sweep.lock` (the
//! plan: base scene, grid and their hashes, written before any work), and at the end
//! `maps/<id>.png` (every map on one colour scale), `report.png` and `results.json`; while a
//! sweep or a merge writes there, `sweep.pid` locks the folder (see [`FolderLock`]).
//! `--resume` keeps the rows of `results.csv` whose design is in the grid (and whose field is
//! there), refuses a folder swept with another base scene, and runs the rest. Shard `I/N` runs
//! the designs whose index is `I − 1` modulo `N`; [`merge`] puts shard folders back together.

pub mod embedded;
mod field;
mod folder_error;
mod folder_lock;
mod grid;
mod merge;
mod plan;
mod rows;
mod run;
mod shard;
mod store;
mod values;

pub use field::StoredField;
pub use folder_error::{StoreError, write_atomic};
pub use folder_lock::{FolderLock, LOCK_FILE};
pub use grid::{Column, Design};
pub use merge::merge;
pub use plan::{Axis, Plan, SHORT_NAMES};
pub use rows::{Counts, FIGURE_COLUMNS, Row, column_names, counts, csv_header};
pub use run::{Options, Outcome, Progress, cores, pool, run, workers_for};
pub use shard::Shard;
pub use store::{OtherSweep, ReadReport, holds_this_sweep, read_lock};
pub use values::{as_number, fnv_hex, show_value, unit_of};

/// Why a sweep did not go through: bad input, found before any work (exit 2), or a failure
/// while running (exit 1).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The sweep file, an option or the output folder is not what was expected.
    #[error("{0}")]
    BadInput(String),
    /// The base scene breaks a bound or does not parse.
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// The output folder could not be prepared before any work.
    #[error(transparent)]
    Folder(StoreError),
    /// The output folder could not be read or written while running.
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error("{0}")]
    Run(String),
}

impl SweepError {
    /// Bad input (the user can fix it before any work), rather than a failure while running.
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            SweepError::BadInput(_) | SweepError::Scene(_) | SweepError::Folder(_)
        )
    }
}
