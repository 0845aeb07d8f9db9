//! The frontier in the explorer: `b` finds, for every combination of the other axes, where
//! along a swept number (the sorted column when it is one, else the first) the verdict
//! changes, by the headless frontier's root search; its runs fill the table where they fall
//! on the grid, its boundaries show as lines under the results, a chart of the selected
//! design's combination in the detail, and the Run panel counts its runs.

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::symbols::Marker;
use ratatui::text::Line;
use ratatui::widgets::{Axis, Block, Chart, Dataset, GraphType, Paragraph, Widget};

use super::app::{App, Command, Entry, FrontierView};
use super::style::Styles;
use super::worker::Message;
use crate::report::frontier::{boundary_words, found_words};
use crate::study::frontier::{Found, Frontier, Lattice};
use crate::study::sweep::{Design, as_number};

impl App {
    /// The frontier asked for last, if any.
    pub fn frontier(&self) -> Option<&FrontierView> {
        self.frontier.as_ref()
    }

    /// The column `b` searches along: the sorted column when it is a number swept with two
    /// or more values, else the first such column.
    pub(super) fn boundary_column(&self) -> Option<String> {
        let plan = &self.params.plan;
        let searchable = |c: &str| {
            (plan.axes.iter()).any(|a| {
                a.column == c
                    && a.values.len() > 1
                    && a.values.iter().all(|v| as_number(v).is_some())
            })
        };
        let sorted = self.sort_name(self.sort.column);
        if searchable(&sorted) {
            return Some(sorted);
        }
        let first = plan.axes.iter().find(|a| searchable(&a.column));
        first.map(|a| a.column.clone())
    }

    /// Finds the boundary along [`App::boundary_column`] for the edited grid, in a run folder
    /// of its own; the table shows the grid, filled where the search's runs fall on it.
    pub(super) fn find_boundary(&mut self) -> Command {
        if self.running() {
            self.status = "a sweep is running: c cancels it".into();
            return Command::None;
        }
        let Some(column) = self.boundary_column() else {
            self.status = "b: no number is swept with two or more values: a boundary needs a \
                           range (edit a parameter to a list or a range)"
                .into();
            return Command::None;
        };
        let plan = self.params.plan.clone();
        let lattice = match Lattice::asked_with(&plan, &column, "the boundary along") {
            Ok(l) => l,
            Err(e) => {
                self.status = format!("b: {e}");
                return Command::None;
            }
        };
        self.frontier = Some(FrontierView {
            column: column.clone(),
            combos: lattice.combos.len(),
            grid_runs: lattice.combos.len() * lattice.grid_values,
            result: None,
        });
        // The rows of the last run of this scene and columns are the search's too: it runs in
        // that folder and keeps them (its runs between the grid's values are rows there too).
        let resume = self.run_dir.is_some()
            && plan.base_hash == self.run_base_hash
            && plan.columns() == self.table_plan.columns()
            && self.entries.iter().any(|e| e.row.is_some());
        let dir = if resume {
            self.entries = super::runs::carry_rows(&self.entries, &plan);
            self.run_dir.clone().expect("checked")
        } else {
            self.new_run_folder(&plan)
        };
        self.begin_grid_run(&plan, &dir, 2 * lattice.combos.len());
        self.status = format!("finding the boundary along {column}");
        Command::Frontier {
            lattice: Box::new(lattice),
            dir,
            resume,
        }
    }

    /// A frontier's report: a round's runs, or what it found.
    pub(super) fn on_frontier_message(&mut self, m: Message) {
        match m {
            Message::Round { to_run } => self.to_run = self.done + to_run,
            Message::Frontier(found) => {
                if let Some(view) = self.frontier.as_mut() {
                    self.status = format!(
                        "boundary along {}: {} runs against the grid's {}",
                        view.column,
                        found.runs(),
                        view.grid_runs
                    );
                    view.result = Some(*found);
                }
            }
            _ => {}
        }
    }

    /// The table's entry for a row: its design, or the grid's design with the same values (a
    /// frontier's run on the lattice).
    pub(super) fn entry_index_of(&self, design: &str) -> Option<usize> {
        let exact = self.entries.iter().position(|e| e.design.id == design);
        exact.or_else(|| {
            let hash = Design::values_hash(design)?;
            (self.entries.iter()).position(|e| Design::values_hash(&e.design.id) == Some(hash))
        })
    }
}

/// The frontier's line of the Run panel: what it searches and its runs against the grid's.
pub(super) fn run_line<'a>(app: &App, st: &Styles) -> Option<Line<'a>> {
    let view = app.frontier()?;
    let text = match &view.result {
        None => format!(
            "boundary along {}: {} runs so far for {} combinations (the grid: {})",
            view.column, app.done, view.combos, view.grid_runs
        ),
        Some(f) => format!(
            "boundary along {}: {} runs against the grid's {} ({:.2}×)",
            view.column,
            f.runs(),
            view.grid_runs,
            f.runs() as f64 / view.grid_runs.max(1) as f64
        ),
    };
    Some(Line::styled(text, st.title()))
}

/// Draws the boundaries under the results (a bordered block at the bottom of `area`, at most
/// half of it) when a frontier has found them; returns the area left for the table.
pub(super) fn split_boundaries(app: &App, area: Rect, buf: &mut Buffer, st: &Styles) -> Rect {
    let lines = boundary_lines(app, st);
    let Some(view) = app.frontier().filter(|_| !lines.is_empty()) else {
        return area;
    };
    let h = (lines.len() as u16 + 2).min(area.height / 2);
    let [table, bottom] = Layout::vertical([Constraint::Min(3), Constraint::Length(h)]).areas(area);
    let title = format!(" Boundary along {} (b) ", view.column);
    Paragraph::new(lines)
        .block(Block::bordered().title(title).border_style(st.dim()))
        .render(bottom, buf);
    table
}

/// Draws the chart of the selected design's combination at the bottom of `area` when a
/// frontier has found it and there is room; returns the area left (for the map).
pub(super) fn split_chart(
    app: &App,
    entry: &Entry,
    area: Rect,
    buf: &mut Buffer,
    st: &Styles,
) -> Rect {
    let found = app.frontier().and_then(|v| v.result.as_ref());
    if found.and_then(|f| line_of(f, entry)).is_none() || area.height < 16 {
        return area;
    }
    let [map, chart] = Layout::vertical([Constraint::Min(5), Constraint::Length(10)]).areas(area);
    render_chart(app, entry, chart, buf, st);
    map
}

/// The boundaries as lines under the results: one per combination.
fn boundary_lines<'a>(app: &App, st: &Styles) -> Vec<Line<'a>> {
    let Some(f) = app.frontier().and_then(|v| v.result.as_ref()) else {
        return Vec::new();
    };
    f.lines
        .iter()
        .map(|line| {
            let combo = crate::report::frontier::combo_words(line);
            let style = match &line.found {
                Found::Boundaries(_) => st.good(),
                Found::Whole { over, .. } if over.is_empty() => st.good(),
                Found::Whole { .. } => st.bad(),
                _ => st.warn(),
            };
            let words = match &line.found {
                Found::Boundaries(bs) => {
                    let parts: Vec<String> = bs
                        .iter()
                        .map(|b| {
                            let d = crate::report::frontier::decimals(f);
                            format!(
                                "{} (MARGINAL {:.d$}–{:.d$})",
                                boundary_words(f, b),
                                b.interval[0],
                                b.interval[1]
                            )
                        })
                        .collect();
                    parts.join(" and ")
                }
                _ => found_words(f, line),
            };
            Line::styled(
                format!("{combo}: {words} · {} runs", line.runs.len()),
                style,
            )
        })
        .collect()
}

/// The frontier line of an entry's combination (its other axes' values), if any.
fn line_of<'f>(f: &'f Frontier, entry: &Entry) -> Option<&'f crate::study::frontier::Line> {
    f.lines.iter().find(|line| {
        line.values.iter().all(|(c, _, v)| {
            let here = entry.params.iter().find(|(name, _)| name == c);
            here.is_some_and(|(_, x)| {
                as_number(x).zip(as_number(v)).is_some_and(|(a, b)| a == b) || x == v
            })
        })
    })
}

/// The chart of the selected design's combination: its runs' max shear over the locking
/// angle against the axis, the limit, and each boundary as a vertical line.
/// A line's runs along the axis: the max shear over the locking angle and the max tension
/// over the break, each sorted along the axis, and the top of the chart.
type Points = Vec<(f64, f64)>;
fn figures_along(f: &Frontier, line: &crate::study::frontier::Line) -> (Points, Points, f64) {
    let along = |figure: &dyn Fn(&crate::study::sweep::Row) -> Option<f64>| {
        let mut pts: Points = (line.runs.iter())
            .filter_map(|p| {
                let row = f.rows.iter().find(|r| r.design == p.design)?;
                Some((p.value, figure(row)?))
            })
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts
    };
    let shear = along(&|r| Some(r.max_shear_deg? / f.limits.locking_angle_deg));
    let tension = along(&|r| Some(r.max_tension_n? / f.limits.break_tension_n));
    let top = (shear.iter().chain(&tension))
        .map(|p| p.1)
        .fold(1.2_f64, f64::max)
        .min(3.0);
    (shear, tension, top)
}

fn render_chart(app: &App, entry: &Entry, area: Rect, buf: &mut Buffer, st: &Styles) {
    let Some(f) = app.frontier().and_then(|v| v.result.as_ref()) else {
        return;
    };
    let Some(line) = line_of(f, entry) else {
        return;
    };
    let (shear, sorted_tension, top) = figures_along(f, line);
    let [lo, hi] = f.range;
    let limit = [(lo, 1.0), (hi, 1.0)];
    let bounds: Vec<[(f64, f64); 2]> = match &line.found {
        Found::Boundaries(bs) => bs
            .iter()
            .map(|b| [(b.value, 0.0), (b.value, top)])
            .collect(),
        _ => Vec::new(),
    };
    let mut sets = vec![
        Dataset::default()
            .name("shear / locking")
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(st.title())
            .data(&shear),
        Dataset::default()
            .name("tension / break")
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(st.warn())
            .data(&sorted_tension),
        Dataset::default()
            .name("limit")
            .marker(Marker::Dot)
            .graph_type(GraphType::Line)
            .style(st.dim())
            .data(&limit),
    ];
    for (k, b) in bounds.iter().enumerate() {
        let name = if k == 0 { "boundary" } else { "" };
        sets.push(
            Dataset::default()
                .name(name)
                .marker(Marker::Braille)
                .graph_type(GraphType::Line)
                .style(st.bad())
                .data(b),
        );
    }
    let d = crate::report::frontier::decimals(f);
    let unit = crate::report::frontier::unit(f);
    Chart::new(sets)
        .x_axis(
            Axis::default()
                .title(format!("{} {unit}", f.column))
                .bounds([lo, hi])
                .labels([format!("{lo:.d$}"), format!("{hi:.d$}")])
                .style(Style::default()),
        )
        .y_axis(Axis::default().bounds([0.0, top]).labels([
            "0".to_string(),
            format!("{:.1}", top / 2.0),
            format!("{top:.1}"),
        ]))
        .render(area, buf);
}
