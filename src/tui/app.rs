//! The explorer's state (what each key does to it: `keys.rs`; starting runs: `runs.rs`). No
//! terminal here: keys come in as
//! `KeyEvent`s, worker reports as `Message`s, and what needs the outside world (a sweep, an
//! export, quitting) goes out as a `Command`, so that all of it can be tested directly.

use std::cmp::Ordering;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use crate::study::sweep::{Design, Plan, Row, StoredField, counts};
use crate::verdict::{Limits, Verdict};

use super::error::{FieldError, ParamError, WorkError};
use super::params::Parameters;
use super::worker::Message;

/// Which panel the arrow keys move in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Focus {
    Parameters,
    Results,
}

/// What the keys are doing.
#[derive(Clone, Debug, PartialEq)]
pub enum Mode {
    Normal,
    /// Editing the selected parameter: the text typed and what is wrong with it.
    Editing {
        buffer: String,
        error: Option<ParamError>,
    },
    /// Asking where to export.
    Exporting {
        buffer: String,
    },
    Help,
    /// The selected design's detail over the whole screen.
    Detail,
}

/// Where the sweep is.
#[derive(Clone, Debug, PartialEq)]
pub enum RunState {
    Idle,
    Running,
    /// Cancel asked; waiting for the designs on the workers to stop.
    Stopping,
    Finished {
        wall_s: f64,
    },
    Cancelled {
        wall_s: f64,
    },
    Failed(String),
}

/// What the event loop must do after a key.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    None,
    Quit,
    /// Run `plan` into `dir`, keeping the rows already there when `resume`; only the designs
    /// of `only` (by id) when it is given.
    Start {
        plan: Box<Plan>,
        dir: PathBuf,
        resume: bool,
        only: Option<HashSet<String>>,
    },
    Cancel,
    /// Export the run folders the table's rows come from: the first into `to`, each other
    /// (designs re-run finer) into `to/<its name>`.
    Export {
        from: Vec<PathBuf>,
        to: PathBuf,
    },
    /// Find the boundary along the lattice's axis into `dir` (see [`super::frontier`]),
    /// keeping the rows there when `resume`.
    Frontier {
        lattice: Box<crate::study::frontier::Lattice>,
        dir: PathBuf,
        resume: bool,
    },
    /// Solve design `design` again and write its maps, VTU and summary into `dir`.
    WriteFiles {
        design: String,
        scene: Box<crate::scene::Scene>,
        dir: PathBuf,
    },
}

/// One line of the results table: a design of the grid, and its row once it has one.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub design: Design,
    pub params: Vec<(String, toml::Value)>,
    pub row: Option<Row>,
    /// The design's own limits: the locking angle (°) and the break tension (N), which a
    /// sweep may vary.
    pub limits: Limits,
    /// The run folder its row and field are in (a design re-run finer has its own), and the
    /// accuracy level its row was run at.
    pub dir: Option<PathBuf>,
    pub accuracy: Option<crate::accuracy::Accuracy>,
}

/// How long a status message stays in the Run panel, s.
pub const STATUS_S: f64 = 12.0;

/// The columns of the results table one can sort by, after the parameters.
pub const FIGURE_COLUMNS: [&str; 7] = [
    "#", "shear", "tension", "force", "verdict", "time", "wrinkles",
];

/// The sort: a column (0 = design number, 1..=P the parameters, then the figures) and its
/// direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sort {
    pub column: usize,
    pub descending: bool,
}

/// The explorer. Its state is read through the methods below (the view, the keys and the
/// runs, in this module, see the fields).
pub struct App {
    pub(super) params: Parameters,
    /// The plan whose designs the table shows (the parameters may have been edited since).
    pub(super) table_plan: Plan,
    pub(super) entries: Vec<Entry>,
    pub(super) focus: Focus,
    pub(super) mode: Mode,
    /// The selected parameter.
    pub(super) cursor: usize,
    /// The selected line of the visible results.
    pub(super) selected: usize,
    pub(super) sort: Sort,
    pub(super) feasible_only: bool,
    pub(super) run: RunState,
    /// Designs to run in this run, and finished in it.
    pub(super) to_run: usize,
    pub(super) done: usize,
    /// Seconds since the explorer opened (set by the event loop), and when the run started.
    pub(super) now_s: f64,
    pub(super) run_started_s: f64,
    /// A line for the user: the export's path, an error.
    pub(super) status: String,
    /// The status as last seen by the clock, and since when (s): a message fades after
    /// [`STATUS_S`] so the Run panel does not keep stale news.
    pub(super) status_seen: (String, f64),
    /// Where the runs of this session are written.
    pub(super) session: PathBuf,
    pub(super) runs: usize,
    /// The folder of the latest run, and the hash of the base scene it was run on (the
    /// table's may differ since: limits judged again).
    pub(super) run_dir: Option<PathBuf>,
    pub(super) run_base_hash: String,
    /// The folder of the run in progress (or the last), and its accuracy level.
    pub(super) active_dir: Option<PathBuf>,
    pub(super) active_accuracy: Option<crate::accuracy::Accuracy>,
    /// Shear fields of finished designs, read from the run folder when first selected.
    pub(super) fields: HashMap<String, Result<StoredField, FieldError>>,
    /// False where the terminal has no colours: symbols and shades instead.
    pub(super) colour: bool,
    /// Where the next export goes by default.
    pub(super) export_dir: PathBuf,
    /// Which map the detail shows: the shear, the yarn tension or the wrinkles.
    pub(super) detail_map: DetailMap,
    /// Each design's own files (maps, VTU), by id: written, or being written (empty).
    pub(super) design_files: HashMap<String, Result<Vec<PathBuf>, WorkError>>,
    /// The boundary asked for with `b`, and what it found.
    pub(super) frontier: Option<FrontierView>,
}

/// A frontier asked for with `b` (`tui/frontier.rs`): along which column, for how many
/// combinations against how many runs of the grid, and what it found once done.
#[derive(Clone, Debug)]
pub struct FrontierView {
    pub column: String,
    pub combos: usize,
    pub grid_runs: usize,
    pub result: Option<crate::study::frontier::Frontier>,
}

/// The map the detail shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum DetailMap {
    Shear,
    /// The larger yarn tension of each element (`t`).
    Tension,
    /// The wrinkle amplitude (`z`), where the scene has bending.
    Wrinkles,
}

impl DetailMap {
    /// `map` if it is not shown, else back to the shear: what its key does.
    pub(super) fn toggled(self, map: DetailMap) -> DetailMap {
        if self == map { DetailMap::Shear } else { map }
    }
}

pub(super) fn entries_of(plan: &Plan) -> Vec<Entry> {
    let columns = plan.columns();
    let base = Limits::of(&plan.base_scene);
    let swept = plan.axes.iter().any(|a| {
        a.values.len() > 1
            && matches!(
                a.key.as_str(),
                "fabric.locking_angle_deg" | "fabric.break_tension_n"
            )
    });
    plan.designs()
        .into_iter()
        .map(|d| {
            let limits = if swept {
                plan.design_scene(&d).map_or(base, |s| Limits::of(&s))
            } else {
                base
            };
            Entry {
                params: plan.params(&columns, &d),
                design: d,
                row: None,
                limits,
                dir: None,
                accuracy: None,
            }
        })
        .collect()
}

fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

fn cmp_option(a: Option<f64>, b: Option<f64>) -> Ordering {
    match (a, b) {
        (Some(a), Some(b)) => a.total_cmp(&b),
        (Some(_), None) => Ordering::Less,
        (None, Some(_)) => Ordering::Greater,
        (None, None) => Ordering::Equal,
    }
}

impl App {
    pub fn new(params: Parameters, session: PathBuf, colour: bool) -> App {
        let plan = params.plan.clone();
        let export_dir = PathBuf::from(format!("{}-export", plan.name()));
        App {
            entries: entries_of(&plan),
            table_plan: plan,
            params,
            focus: Focus::Results,
            mode: Mode::Normal,
            cursor: 0,
            selected: 0,
            sort: Sort {
                column: 0,
                descending: false,
            },
            feasible_only: false,
            run: RunState::Idle,
            to_run: 0,
            done: 0,
            now_s: 0.0,
            status_seen: (String::new(), 0.0),
            run_started_s: 0.0,
            status: String::new(),
            session,
            runs: 0,
            run_dir: None,
            run_base_hash: String::new(),
            active_dir: None,
            active_accuracy: None,
            fields: HashMap::new(),
            colour,
            export_dir,
            detail_map: DetailMap::Shear,
            design_files: HashMap::new(),
            frontier: None,
        }
    }

    /// The parameters as edited.
    pub fn params(&self) -> &Parameters {
        &self.params
    }

    /// The plan whose designs the table shows.
    pub fn table_plan(&self) -> &Plan {
        &self.table_plan
    }

    /// The lines of the results table, in grid order (see [`App::visible`]).
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    pub fn focus(&self) -> Focus {
        self.focus
    }

    /// The selected parameter line.
    pub fn cursor(&self) -> usize {
        self.cursor
    }

    pub fn mode(&self) -> &Mode {
        &self.mode
    }

    pub fn sort(&self) -> Sort {
        self.sort
    }

    /// Where the sweep is.
    pub fn run_state(&self) -> &RunState {
        &self.run
    }

    /// The line for the user (the export's path, an error), fresh or not.
    pub fn status(&self) -> &str {
        &self.status
    }

    /// Seconds since the explorer opened (the event loop sets it on every tick).
    pub fn set_now(&mut self, now_s: f64) {
        self.now_s = now_s;
    }

    /// The runs started in this session.
    pub fn runs(&self) -> usize {
        self.runs
    }

    /// The folder of the latest run of the grid.
    pub fn run_dir(&self) -> Option<&Path> {
        self.run_dir.as_deref()
    }

    /// The shear field of design `id` as read from its run folder, if it was.
    pub fn field(&self, id: &str) -> Option<&Result<StoredField, FieldError>> {
        self.fields.get(id)
    }

    /// Keeps the field of design `id`, read elsewhere, as if read from its run folder.
    pub fn keep_field(&mut self, id: String, field: StoredField) {
        self.fields.insert(id, Ok(field));
    }

    pub fn running(&self) -> bool {
        matches!(self.run, RunState::Running | RunState::Stopping)
    }

    /// Notes the time the status changed (called on every tick).
    pub fn note_status_time(&mut self) {
        if self.status != self.status_seen.0 {
            self.status_seen = (self.status.clone(), self.now_s);
        }
    }

    /// The status while it is news: set less than [`STATUS_S`] ago.
    pub fn fresh_status(&self) -> Option<&str> {
        let fresh = self.status != self.status_seen.0 || self.now_s - self.status_seen.1 < STATUS_S;
        (!self.status.is_empty() && fresh).then_some(self.status.as_str())
    }

    /// The parameters were edited since the table's designs were laid out.
    pub fn edited(&self) -> bool {
        self.params.plan.sweep_hash != self.table_plan.sweep_hash
    }

    /// The table's fabric bends: its designs have a wrinkle figure, and the table a column.
    pub(super) fn bends(&self) -> bool {
        self.table_plan.base_scene.fabric.bending_rigidity.is_some()
    }

    /// The number of sortable columns (the wrinkles last, where the fabric bends).
    pub(super) fn sort_columns(&self) -> usize {
        let wrinkles = usize::from(!self.bends());
        self.table_plan.columns().len() + FIGURE_COLUMNS.len() - wrinkles
    }

    /// The column `s` sorts by after `column`: from `#` to the figures first (shear, tension,
    /// force, verdict, time, wrinkles), then the parameters, then `#` again.
    pub(super) fn next_sort_column(&self, column: usize) -> usize {
        let p = self.table_plan.columns().len();
        let figures = (p + 1)..self.sort_columns();
        let order: Vec<usize> = std::iter::once(0).chain(figures).chain(1..=p).collect();
        let at = order.iter().position(|&c| c == column).unwrap_or(0);
        order[(at + 1) % order.len()]
    }

    /// The name of a sortable column.
    pub fn sort_name(&self, column: usize) -> String {
        let cols = self.table_plan.columns();
        match column {
            0 => "#".into(),
            c if c <= cols.len() => cols[c - 1].name.clone(),
            c => FIGURE_COLUMNS[c - cols.len()].into(),
        }
    }

    fn sort_value(&self, e: &Entry, column: usize) -> Option<f64> {
        let p = e.params.len();
        let row = e.row.as_ref();
        match column {
            0 => Some(e.design.index as f64),
            c if c <= p => number(&e.params[c - 1].1),
            c => match c - p {
                1 => row.and_then(|r| r.max_shear_deg),
                2 => row.and_then(|r| r.max_tension_n),
                3 => row.and_then(|r| r.punch_force_n),
                4 => row.map(|r| r.verdict as u8 as f64),
                5 => row.and_then(|r| r.wall_s),
                _ => row.and_then(|r| r.max_wrinkle_mm),
            },
        }
    }

    /// The lines of the results table, as indices into `entries`, filtered and sorted.
    pub fn visible(&self) -> Vec<usize> {
        let mut v: Vec<usize> = (0..self.entries.len())
            .filter(|&i| {
                !self.feasible_only
                    || self.entries[i]
                        .row
                        .as_ref()
                        .is_some_and(|r| r.verdict == Verdict::Feasible)
            })
            .collect();
        let col = self.sort.column;
        v.sort_by(|&a, &b| {
            let (ea, eb) = (&self.entries[a], &self.entries[b]);
            let (va, vb) = (self.sort_value(ea, col), self.sort_value(eb, col));
            // Designs without a figure go last in either direction.
            let o = match (va, vb) {
                (Some(x), Some(y)) if self.sort.descending => y.total_cmp(&x),
                _ => cmp_option(va, vb),
            };
            o.then(ea.design.index.cmp(&eb.design.index))
        });
        v
    }

    /// The selected entry, if the table has lines.
    pub fn selected_entry(&self) -> Option<&Entry> {
        let v = self.visible();
        v.get(self.selected.min(v.len().saturating_sub(1)))
            .map(|&i| &self.entries[i])
    }

    /// The selected design's shear field, as read when it was selected (drawing reads no
    /// files); `None` while the design has no map.
    pub fn selected_field(&self) -> Option<&Result<StoredField, FieldError>> {
        let id = self.selected_map_id()?;
        self.fields.get(id)
    }

    /// The design id of the selected entry, when its row has a map.
    fn selected_map_id(&self) -> Option<&str> {
        self.selected_entry()
            .and_then(|e| e.row.as_ref())
            .filter(|r| r.map.is_some())
            .map(|r| r.design.as_str())
    }

    /// Reads the selected design's field from its run folder, unless it was read before:
    /// after every key and report, so that the selection, a design finishing and the detail
    /// opening find it there. A read that failed is tried again (a resumed run renames the
    /// files of renumbered designs when its workers start).
    pub(super) fn load_selected_field(&mut self) {
        let Some(id) = self.selected_map_id().map(str::to_string) else {
            return;
        };
        if matches!(self.fields.get(&id), Some(Ok(_))) {
            return;
        }
        let dir = self.selected_entry().and_then(|e| e.dir.clone());
        let read = match dir.as_ref().or(self.run_dir.as_ref()) {
            Some(dir) => StoredField::read(dir, &id).map_err(FieldError::from),
            None => Err(FieldError::NoRunFolder),
        };
        self.fields.insert(id, read);
    }

    /// The run folders the table's rows come from, the one with the most rows first.
    pub fn row_dirs(&self) -> Vec<PathBuf> {
        let mut count: Vec<(PathBuf, usize)> = Vec::new();
        for e in self.entries.iter().filter(|e| e.row.is_some()) {
            let Some(d) = e.dir.clone().or_else(|| self.run_dir.clone()) else {
                continue;
            };
            match count.iter_mut().find(|(p, _)| *p == d) {
                Some((_, n)) => *n += 1,
                None => count.push((d, 1)),
            }
        }
        count.sort_by_key(|c| std::cmp::Reverse(c.1));
        count.into_iter().map(|(d, _)| d).collect()
    }

    /// Counts over the table: (with a row, feasible).
    pub fn counts(&self) -> (usize, usize) {
        let rows = self.entries.iter().filter_map(|e| e.row.as_ref());
        let c = counts(rows);
        let done = c.feasible + c.marginal + c.infeasible + c.failed + c.invalid;
        (done, c.feasible)
    }

    /// Seconds left, from the pace of the designs finished in this run.
    pub fn eta_s(&self) -> Option<f64> {
        if !self.running() || self.done == 0 {
            return None;
        }
        let elapsed = self.now_s - self.run_started_s;
        Some(elapsed / self.done as f64 * self.to_run.saturating_sub(self.done) as f64)
    }

    /// A report from the workers.
    pub fn on_message(&mut self, m: Message) {
        self.apply_message(m);
        self.load_selected_field();
    }

    fn apply_message(&mut self, m: Message) {
        match m {
            Message::Started { to_run, kept } => {
                self.to_run = to_run;
                self.done = 0;
                if kept > 0 {
                    self.status = format!("{kept} finished designs kept: only the others run");
                }
            }
            Message::Row(row) => {
                let at = self.entry_index_of(&row.design);
                if let Some(e) = at.map(|i| &mut self.entries[i]) {
                    if row.verdict != Verdict::Invalid {
                        self.done += 1;
                    }
                    // A design run again (finer) has a new field: read it afresh.
                    self.fields.remove(&row.design);
                    e.dir = self.active_dir.clone();
                    e.accuracy = self.active_accuracy;
                    e.row = Some(*row);
                } else if self.frontier.is_some() {
                    // A frontier's run between the grid's values: counted, not in the table.
                    self.done += 1;
                }
            }
            Message::Finished {
                stopped,
                wall_s,
                error,
            } => {
                self.run = match (error, stopped) {
                    (Some(e), _) => RunState::Failed(e),
                    (None, true) => RunState::Cancelled { wall_s },
                    (None, false) => RunState::Finished { wall_s },
                };
            }
            m @ (Message::Round { .. } | Message::Frontier(_)) => self.on_frontier_message(m),
            Message::Written { design, result } => {
                if let Err(e) = &result {
                    self.status = format!("writing the files of {design} failed: {e}");
                }
                self.design_files.insert(design, result);
            }
            Message::Exported(result) => {
                self.status = match result {
                    Ok(files) => format!(
                        "exported to {}: {}",
                        std::fs::canonicalize(&self.export_dir)
                            .unwrap_or_else(|_| self.export_dir.clone())
                            .display(),
                        files
                            .iter()
                            .map(|f| f
                                .strip_prefix(&self.export_dir)
                                .unwrap_or(f)
                                .display()
                                .to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                    Err(e) => format!("export failed: {e}"),
                };
            }
        }
    }

    /// With no results on the table and no run going, the table shows the edited grid.
    pub(super) fn follow_edits(&mut self) {
        if self.running() {
            return;
        }
        if self.entries.iter().all(|e| e.row.is_none()) {
            self.table_plan = self.params.plan.clone();
            self.entries = entries_of(&self.table_plan);
            self.selected = 0;
            self.sort.column = self.sort.column.min(self.sort_columns() - 1);
        } else if self.only_the_limits_changed() {
            // The limits change verdicts, not figures: judge the rows again, run nothing.
            let limits = Limits::of(&self.params.plan.base_scene);
            let old = Limits::of(&self.table_plan.base_scene);
            let words = [
                (old.locking_angle_deg != limits.locking_angle_deg).then(|| {
                    format!(
                        "the locking angle of {}°",
                        crate::show::Num(limits.locking_angle_deg)
                    )
                }),
                (old.break_tension_n != limits.break_tension_n).then(|| {
                    format!(
                        "the break tension of {} N",
                        crate::show::Num(limits.break_tension_n)
                    )
                }),
            ];
            for e in &mut self.entries {
                e.limits = limits;
                if let Some(row) = e.row.as_mut() {
                    row.rejudge(limits);
                }
            }
            self.table_plan = self.params.plan.clone();
            let against: Vec<String> = words.into_iter().flatten().collect();
            self.status = format!("verdicts judged again against {}", against.join(" and "));
        }
    }

    /// The edited parameters differ from the table's only in the limits (the locking angle
    /// and the break tension, neither swept).
    fn only_the_limits_changed(&self) -> bool {
        let (new, old) = (&self.params.plan, &self.table_plan);
        let swept = |p: &Plan| {
            p.axes.iter().any(|a| {
                a.values.len() > 1
                    && matches!(
                        a.key.as_str(),
                        "fabric.locking_angle_deg" | "fabric.break_tension_n"
                    )
            })
        };
        let mut same = old.base_scene.clone();
        same.fabric.locking_angle_deg = new.base_scene.fabric.locking_angle_deg;
        same.fabric.break_tension_n = new.base_scene.fabric.break_tension_n;
        new.base_scene != old.base_scene
            && same == new.base_scene
            && new.axes == old.axes
            && !swept(new)
    }

    pub(super) fn move_selection(&mut self, delta: isize) {
        match self.focus {
            Focus::Parameters => {
                let n = self.params.fields.len() as isize;
                self.cursor = (self.cursor as isize + delta).clamp(0, n - 1) as usize;
            }
            Focus::Results => {
                let n = self.visible().len() as isize;
                self.selected = (self.selected as isize + delta).clamp(0, (n - 1).max(0)) as usize;
            }
        }
    }

    /// The export folder that does not hold results yet: `NAME-export`, `NAME-export-2`, …
    pub(super) fn free_export_dir(&self) -> PathBuf {
        let base = self.export_dir.clone();
        // A folder of the user's is not written into; one with results is another export.
        let taken = |p: &Path| p.join("results.csv").exists() || !crate::files::folder_is_free(p);
        if !taken(&base) {
            return base;
        }
        (2..)
            .map(|k| PathBuf::from(format!("{}-{k}", base.display())))
            .find(|p| !taken(p))
            .expect("some folder is free")
    }
}
