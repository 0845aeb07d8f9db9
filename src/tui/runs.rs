//! Starting runs from the explorer: the grid (or its resume after a cancel), and the marginal
//! designs again one level finer.

use std::collections::HashSet;

use super::app::{App, Command, RunState, entries_of};
use crate::accuracy::Accuracy;
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
            && plan.base_hash == self.table_plan.base_hash
            && self.run_dir.is_some();
        // The grid changed (a value added to a range) on the same scene and columns: a design
        // is its values, so the finished ones keep their rows and only the new ones run, in
        // the same folder (the store renumbers the kept rows' files).
        let regrid = !resume
            && !self.running()
            && plan.base_hash == self.table_plan.base_hash
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
            self.runs += 1;
            self.entries = entries_of(&plan);
            self.fields.clear();
            self.selected = 0;
            self.session.join(format!("run-{}", self.runs))
        };
        self.status.clear();
        self.begin_run(plan, dir, resume || regrid, None)
    }

    /// The run state of a run that starts now, and the command that starts it.
    fn begin_run(
        &mut self,
        plan: crate::study::sweep::Plan,
        dir: std::path::PathBuf,
        resume: bool,
        only: Option<HashSet<String>>,
    ) -> Command {
        self.table_plan = plan.clone();
        self.run_dir = Some(dir.clone());
        self.run = RunState::Running;
        self.to_run = 0;
        self.done = 0;
        self.run_started_s = self.now_s;
        Command::Start {
            plan: Box::new(plan),
            dir,
            resume,
            only,
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
        if self.running() {
            self.status = "a sweep is running: c cancels it".into();
            return Command::None;
        }
        let only = self.marginal_ids();
        if only.is_empty() {
            self.status = "no marginal design to re-run".into();
            return Command::None;
        }
        let finer = self.table_accuracy().step(true);
        if finer == self.table_accuracy() {
            self.status = format!(
                "{} marginal designs at fine already: the finest level cannot settle them",
                only.len()
            );
            return Command::None;
        }
        self.params.set_accuracy(finer);
        let plan = self.params.plan.clone();
        for e in &mut self.entries {
            if only.contains(&e.design.id) {
                e.row = None;
            }
        }
        self.runs += 1;
        let dir = self.session.join(format!("run-{}", self.runs));
        self.status = format!("re-running {} marginal designs at {finer}", only.len());
        self.begin_run(plan, dir, false, Some(only))
    }

    /// The accuracy level the table's plan was run at.
    fn table_accuracy(&self) -> Accuracy {
        Accuracy::of_element_size(self.table_plan.base_scene.mesh.element_size)
            .unwrap_or(self.params.accuracy)
    }
}

/// The entries of `plan` with the rows of `old` whose design has the same values (the hash
/// part of its id), renumbered to the new grid.
fn carry_rows(
    old: &[super::app::Entry],
    plan: &crate::study::sweep::Plan,
) -> Vec<super::app::Entry> {
    use crate::study::sweep::Design;
    let hash = |id: &str| Design::values_hash(id).map(str::to_string);
    let rows: std::collections::HashMap<String, &crate::study::sweep::Row> = old
        .iter()
        .filter_map(|e| Some((hash(&e.design.id)?, e.row.as_ref()?)))
        .collect();
    let mut entries = entries_of(plan);
    for e in &mut entries {
        if let Some(row) = hash(&e.design.id).and_then(|h| rows.get(&h)) {
            let mut row = (*row).clone();
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
