//! Starting runs from the explorer: the grid (or its resume after a cancel), and the marginal
//! designs again one level finer.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use super::app::{App, Command, RunState, entries_of};
use crate::accuracy::Accuracy;
use crate::study::sweep::Plan;
use crate::verdict::Verdict;

impl App {
    /// Starts (or, after a cancel of the same grid, resumes) a run of the edited parameters.
    pub(super) fn start(&mut self) -> Command {
        if self.running() {
            self.status = "a sweep is running: c cancels it".into();
            return Command::None;
        }
        let plan = self.params.plan.clone();
        // A cancelled run is resumed only for the same grid on the same scene (the accuracy or
        // the locking angle edited since is another scene: a new run).
        let resume = matches!(self.run, RunState::Cancelled { .. })
            && plan.sweep_hash == self.table_plan.sweep_hash
            && plan.base_hash == self.run_base_hash
            && self.run_dir.is_some();
        // The grid changed (a value added to a range) on the same scene and columns: a design
        // is its values, so the finished ones keep their rows and only the new ones run, in
        // the same folder (the store renumbers the kept rows' files).
        let regrid = !resume
            && !self.running()
            && plan.base_hash == self.run_base_hash
            && plan.columns() == self.table_plan.columns()
            && self.run_dir.is_some()
            && self.entries.iter().any(|e| e.row.is_some());
        let dir = if resume {
            self.run_dir.clone().expect("checked")
        } else if regrid {
            let kept = carry_rows(&self.entries, &plan);
            self.entries = kept;
            self.fields.clear();
            self.selected = 0;
            self.run_dir.clone().expect("checked")
        } else {
            self.new_run_folder(&plan)
        };
        self.status.clear();
        self.frontier = None;
        self.begin_run(plan, dir, resume || regrid)
    }

    /// A new run folder of this session for `plan`'s grid, the table laid out afresh (no
    /// rows, no fields read, the first design selected).
    pub(super) fn new_run_folder(&mut self, plan: &Plan) -> PathBuf {
        self.runs += 1;
        self.entries = entries_of(plan);
        self.fields.clear();
        self.selected = 0;
        self.session.join(format!("run-{}", self.runs))
    }

    /// The run state of a run of the table's grid that starts now, and its command.
    fn begin_run(&mut self, plan: Plan, dir: PathBuf, resume: bool) -> Command {
        self.begin_grid_run(&plan, &dir, 0);
        Command::Start {
            plan: Box::new(plan),
            dir,
            resume,
            only: None,
        }
    }

    /// The table's grid and folder become `plan`'s and `dir`, where a run of its grid (or a
    /// search on it) of `to_run` runs (0: not known yet) starts now.
    pub(super) fn begin_grid_run(&mut self, plan: &Plan, dir: &Path, to_run: usize) {
        self.table_plan = plan.clone();
        self.run_base_hash = plan.base_hash.clone();
        self.run_dir = Some(dir.to_path_buf());
        self.begin_active_run(plan, dir, to_run);
    }

    /// The run state of a run of `to_run` runs (0: not known yet) that starts now into `dir`
    /// (the grid's, or designs re-run finer in a folder of their own: the table's grid and
    /// folder stay).
    fn begin_active_run(&mut self, plan: &Plan, dir: &Path, to_run: usize) {
        self.active_dir = Some(dir.to_path_buf());
        self.active_accuracy = Accuracy::of_element_size(plan.base_scene.mesh.element_size);
        self.run = RunState::Running;
        self.to_run = to_run;
        self.done = 0;
        self.run_started_s = self.now_s;
    }

    /// The run state of designs re-run finer into `dir` that start now, and its command.
    fn begin_rerun(&mut self, plan: Plan, dir: PathBuf, only: HashSet<String>) -> Command {
        self.begin_active_run(&plan, &dir, 0);
        Command::Start {
            plan: Box::new(plan),
            dir,
            resume: false,
            only: Some(only),
        }
    }

    /// The designs whose verdict is MARGINAL.
    pub fn marginal_ids(&self) -> HashSet<String> {
        self.entries
            .iter()
            .filter_map(|e| e.row.as_ref())
            .filter(|r| r.verdict == Verdict::Marginal)
            .map(|r| r.design.clone())
            .collect()
    }

    /// Runs the marginal designs again at the next finer level, in a run folder of their own;
    /// the other designs keep their rows (each row carries its own error band).
    pub(super) fn rerun_marginal(&mut self) -> Command {
        let only = self.marginal_ids();
        if only.is_empty() && !self.running() {
            self.status = "no marginal design to re-run".into();
            return Command::None;
        }
        let what = format!("{} marginal designs", only.len());
        self.rerun_finer(only, &what)
    }

    /// Runs the selected design again one level finer than it was run (from its detail).
    pub(super) fn rerun_selected(&mut self) -> Command {
        let Some(e) = self.selected_entry() else {
            return Command::None;
        };
        if e.row.is_none() {
            self.status = "this design has not run yet: r runs the sweep".into();
            return Command::None;
        }
        let what = format!("design {}", e.design.index);
        let only = HashSet::from([e.design.id.clone()]);
        self.rerun_finer(only, &what)
    }

    /// Runs the designs `only` one level finer than their rows were run, in a run folder of
    /// their own; their rows wait for it, the others keep theirs. The parameters' level stays.
    fn rerun_finer(&mut self, only: HashSet<String>, what: &str) -> Command {
        if self.running() {
            self.status = "a sweep is running: c cancels it".into();
            return Command::None;
        }
        let level = self
            .entries
            .iter()
            .filter(|e| only.contains(&e.design.id))
            .filter_map(|e| e.accuracy)
            .min_by(|a, b| b.element_size_mm().total_cmp(&a.element_size_mm()))
            .unwrap_or_else(|| self.table_accuracy());
        let finer = level.step(true);
        if finer == level {
            self.status = format!("{what} at {level} already: the finest level cannot settle them");
            return Command::None;
        }
        let mut params = self.params.clone();
        params.set_accuracy(finer);
        if params.accuracy != finer || params.plan.axes != self.table_plan.axes {
            self.status =
                "the parameters were edited since the run: r runs the edited grid first".into();
            return Command::None;
        }
        for e in &mut self.entries {
            if only.contains(&e.design.id) {
                e.row = None;
            }
        }
        self.runs += 1;
        let dir = self.session.join(format!("run-{}", self.runs));
        self.status = format!("re-running {what} at {finer}");
        self.begin_rerun(params.plan, dir, only)
    }

    /// The accuracy level the table's plan was run at.
    fn table_accuracy(&self) -> Accuracy {
        Accuracy::of_element_size(self.table_plan.base_scene.mesh.element_size)
            .unwrap_or(self.params.accuracy)
    }
}

/// The entries of `plan` with the rows of `old` whose design has the same values (the hash
/// part of its id), renumbered to the new grid.
pub(super) fn carry_rows(
    old: &[super::app::Entry],
    plan: &crate::study::sweep::Plan,
) -> Vec<super::app::Entry> {
    use crate::study::sweep::Design;
    let hash = |id: &str| Design::values_hash(id).map(str::to_string);
    let rows: std::collections::HashMap<String, &super::app::Entry> = old
        .iter()
        .filter(|e| e.row.is_some())
        .filter_map(|e| Some((hash(&e.design.id)?, e)))
        .collect();
    let mut entries = entries_of(plan);
    for e in &mut entries {
        if let Some(old) = hash(&e.design.id).and_then(|h| rows.get(&h)) {
            let Some(mut row) = old.row.clone() else {
                continue;
            };
            e.dir = old.dir.clone();
            e.accuracy = old.accuracy;
            if row.map.is_some() {
                row.map = Some(format!("maps/{}.png", e.design.id));
            }
            row.design = e.design.id.clone();
            row.index = e.design.index;
            e.row = Some(row);
        }
    }
    entries
}

impl App {
    /// Writes the selected design's own files (shear and tension PNG, VTU, summary), solving
    /// it again at the level its row was run at, into `SESSION/<id>-<level>/`.
    pub(super) fn write_selected_files(&mut self) -> Command {
        let Some(e) = self.selected_entry() else {
            return Command::None;
        };
        if e.row.is_none() {
            self.status = "this design has not run yet: r runs the sweep".into();
            return Command::None;
        }
        let level = e.accuracy.unwrap_or_else(|| self.table_accuracy());
        let scene = match self.table_plan.design_scene(&e.design) {
            Ok(mut scene) => {
                scene.mesh.element_size = level.element_size_mm();
                scene
            }
            Err(err) => {
                self.status = format!("cannot write its files: {err}");
                return Command::None;
            }
        };
        let id = e.design.id.clone();
        if matches!(self.design_files.get(&id), Some(Ok(f)) if f.is_empty()) {
            return Command::None;
        }
        let dir = self.session.join(format!("{id}-{level}"));
        self.design_files.insert(id.clone(), Ok(Vec::new()));
        Command::WriteFiles {
            design: id,
            scene: Box::new(scene),
            dir,
        }
    }
}
