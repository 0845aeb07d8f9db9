//! The feasibility frontier: for every combination of a sweep's other axes, the value of one
//! number axis (`--along r`) where the verdict changes, found by a root search on the
//! governing figure minus its limit rather than by running the whole grid.
//!
//! The axis becomes a lattice of [`lattice::PER_STEP`] values per step of the sweep file's
//! (its range and, by its number of values, the resolution asked for); each run is a design
//! of that lattice plan, run by the sweep machinery into the output folder as a row of
//! `results.csv`, so a killed search loses nothing, `--resume` reruns nothing, and shards,
//! `merge` and `slurm` work as for a sweep. [`search::Search`] proposes the runs; a round runs
//! every combination's next runs in parallel.
//!
//! Each boundary carries an interval: the search's own (the bracket, or half a step around a
//! root two models agree on) widened on each side by the MARGINAL zone, the level's error band
//! of the governing figure over its slope there (where the band holds the limit, the verdict
//! is MARGINAL).

pub mod lattice;
mod run;
pub mod search;

pub use lattice::Lattice;
pub use run::{Options, Progress, search};
pub use search::Governing;

use crate::study::sweep::Row;
use crate::verdict::{Limits, Verdict};

/// Where the verdict changes along the axis, in the axis's unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    pub governing: Governing,
    /// The estimate.
    pub value: f64,
    /// Where the search puts it.
    pub search: [f64; 2],
    /// The search's interval widened by the MARGINAL zone, within the range.
    pub interval: [f64; 2],
    /// The governing figure is under its limit above the boundary (else below).
    pub feasible_above: bool,
}

/// What one combination's search came to.
#[derive(Clone, Debug, PartialEq)]
pub enum Found {
    /// The verdict changes here (one boundary, or two around a window).
    Boundaries(Vec<Boundary>),
    /// The verdict is the same over the range searched: infeasible (the figures over their
    /// limits somewhere in it) or, with none, feasible.
    Whole {
        over: Vec<Governing>,
        range: [f64; 2],
    },
    /// No run at either end answered: why.
    NoAnswer(String),
    /// Stopped before the search ended.
    Stopped,
}

/// One run of a search: its value along the axis, design and verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct RunPoint {
    pub value: f64,
    pub design: String,
    pub verdict: Verdict,
}

/// One combination of the other axes and its boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// The other axes with two or more values: (column, key, value).
    pub values: Vec<(String, String, toml::Value)>,
    pub found: Found,
    /// The runs its search used, along the axis.
    pub runs: Vec<RunPoint>,
    /// The runs that did not answer (failed, or a value that breaks a bound): the value and
    /// why. The range searched stops short of them.
    pub unanswered: Vec<(f64, String)>,
}

/// A frontier: every combination's boundary along the axis.
#[derive(Clone, Debug)]
pub struct Frontier {
    /// The axis searched: its column name and scene key.
    pub column: String,
    pub key: String,
    pub range: [f64; 2],
    /// The sweep file's number of values on the axis, and so the resolution asked for.
    pub grid_values: usize,
    /// The lattice is even in the logarithm (see [`lattice::LOG_SPAN`]).
    pub log: bool,
    /// The base scene's limits (what the charts divide the figures by).
    pub limits: Limits,
    pub lines: Vec<Line>,
    /// Runs run now, and rows found from before.
    pub ran: usize,
    pub kept: usize,
    /// Every row of the folder's lattice plan.
    pub rows: Vec<Row>,
    pub wall_s: f64,
}

impl Frontier {
    /// The runs the searches used.
    pub fn runs(&self) -> usize {
        self.lines.iter().map(|l| l.runs.len()).sum()
    }

    /// The runs of the sweep file's grid over the same combinations.
    pub fn grid_runs(&self) -> usize {
        self.lines.len() * self.grid_values
    }

    /// The resolution asked for: one step of the sweep file's grid (a factor when the axis
    /// is even in the logarithm).
    pub fn resolution(&self) -> f64 {
        let steps = (self.grid_values.max(2) - 1) as f64;
        if self.log {
            (self.range[1] / self.range[0]).powf(1.0 / steps)
        } else {
            (self.range[1] - self.range[0]) / steps
        }
    }
}

/// What a row answers for the search: each figure's margin over its limit and band, or why
/// there is none.
pub fn answer_of(row: &Row, limits: Limits) -> search::Answer {
    if matches!(row.verdict, Verdict::Failed | Verdict::Invalid) {
        let why = row
            .failure
            .clone()
            .unwrap_or_else(|| row.verdict.word().into());
        return search::Answer::None(why);
    }
    let (Some(shear), Some(tension)) = (row.max_shear_deg, row.max_tension_n) else {
        return search::Answer::None("no figures in the row".into());
    };
    let pct = row.max_tension_err_pct.unwrap_or(0.0).abs() / 100.0;
    search::Answer::Margins {
        margin: [
            Some(shear - limits.locking_angle_deg),
            Some(tension - limits.break_tension_n),
            row.max_wrinkle_mm.map(|w| w - limits.wrinkle_limit_mm),
        ],
        band: [
            row.max_shear_err_deg.unwrap_or(0.0).abs(),
            tension.abs() * pct,
            row.max_wrinkle_err_mm.unwrap_or(0.0).abs(),
        ],
    }
}
