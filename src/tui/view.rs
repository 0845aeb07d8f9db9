//! Drawing the explorer: the parameters, the run, the results table, the detail of a design,
//! the progress gauge and the keys; a help window over it on `?`.
//!
//! 80 × 24 and up. From 130 columns the detail pane sits beside the table; below that, Enter
//! opens it over the whole screen.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{
    Block, Cell, Clear, Gauge, Paragraph, Row as TableRow, Table, TableState, Wrap,
};

use crate::report::sheet::Verdict;
use crate::study::sweep::{Row, StoredField, show_value};

use super::app::{App, Entry, Focus, Mode, RunState};
use super::params::Target;
use super::shear_map::{ShearMap, colour};

/// Width from which the detail pane is shown beside the table.
pub const WIDE: u16 = 130;

/// Seconds as `42 s`, `3 min 05 s` or `1 h 02 min`.
pub fn show_duration(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {:02} s", s / 60, s % 60)
    } else {
        format!("{} h {:02} min", s / 3600, (s % 3600) / 60)
    }
}

struct Styles {
    colour: bool,
}

impl Styles {
    fn fg(&self, c: Color) -> Style {
        if self.colour {
            Style::default().fg(c)
        } else {
            Style::default()
        }
    }
    fn good(&self) -> Style {
        self.fg(Color::Green)
    }
    fn bad(&self) -> Style {
        self.fg(Color::Red).add_modifier(Modifier::BOLD)
    }
    fn warn(&self) -> Style {
        self.fg(Color::Yellow)
    }
    fn dim(&self) -> Style {
        if self.colour {
            Style::default().fg(Color::DarkGray)
        } else {
            Style::default()
        }
    }
    fn title(&self) -> Style {
        Style::default().add_modifier(Modifier::BOLD)
    }
    fn selected(&self) -> Style {
        if self.colour {
            Style::default().bg(Color::Blue).fg(Color::White)
        } else {
            Style::default().add_modifier(Modifier::REVERSED)
        }
    }
}

/// The verdict in a word, its symbol and its style.
fn verdict_cell(row: Option<&Row>, app: &App, st: &Styles) -> (String, Style) {
    let Some(r) = row else {
        return (if app.running() { "…" } else { "·" }.into(), st.dim());
    };
    let locking = app.table_plan.base_scene.fabric.locking_angle_deg;
    match r.verdict {
        Verdict::Feasible => ("✓ feasible".into(), st.good()),
        Verdict::Infeasible => {
            let shear = r.max_shear_deg.is_some_and(|s| s > locking);
            (if shear { "✗ shear" } else { "✗ tension" }.into(), st.bad())
        }
        Verdict::Failed => ("! failed".into(), st.warn()),
        Verdict::Invalid => ("- invalid".into(), st.dim()),
    }
}

fn fixed(v: Option<f64>, decimals: usize) -> String {
    v.map(|v| format!("{v:.decimals$}")).unwrap_or_default()
}

/// Draws the whole explorer.
pub fn draw(frame: &mut Frame, app: &mut App) {
    let st = Styles { colour: app.colour };
    let area = frame.area();
    let [title, main, gauge, keys] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Min(8),
        Constraint::Length(1),
        Constraint::Length(1),
    ])
    .areas(area);
    draw_title(frame, app, title, &st);
    if app.mode == Mode::Detail {
        draw_detail(frame, app, main, &st);
    } else {
        let top_height = (app.params.fields.len() as u16 + 2).min(main.height.saturating_sub(5));
        let [top, bottom] =
            Layout::vertical([Constraint::Length(top_height), Constraint::Min(3)]).areas(main);
        let [params, run] =
            Layout::horizontal([Constraint::Percentage(55), Constraint::Percentage(45)]).areas(top);
        draw_parameters(frame, app, params, &st);
        draw_run(frame, app, run, &st);
        if area.width >= WIDE {
            let [table, detail] =
                Layout::horizontal([Constraint::Length(84), Constraint::Min(40)]).areas(bottom);
            draw_table(frame, app, table, &st);
            draw_detail(frame, app, detail, &st);
        } else {
            draw_table(frame, app, bottom, &st);
        }
    }
    draw_gauge(frame, app, gauge, &st);
    draw_keys(frame, app, keys, &st);
    match &app.mode {
        Mode::Help => draw_help(frame, area, &st),
        Mode::Exporting { buffer } => draw_export_prompt(frame, area, buffer, &st),
        _ => {}
    }
}

fn draw_title(frame: &mut Frame, app: &App, area: Rect, st: &Styles) {
    let p = &app.params;
    let err = p.accuracy.error();
    let text = format!(
        " wovenform · {} · {} designs · {} ±{:.1}° · locking {}°",
        p.source.title,
        p.plan.len(),
        p.accuracy,
        err.max_shear_deg,
        show_value(&toml::Value::Float(p.locking_angle_deg)),
    );
    frame.render_widget(Paragraph::new(Line::styled(text, st.title())), area);
}

fn draw_parameters(frame: &mut Frame, app: &App, area: Rect, st: &Styles) {
    let focused = app.focus == Focus::Parameters;
    let mut lines = Vec::new();
    for (i, f) in app.params.fields.iter().enumerate() {
        let here = focused && i == app.cursor;
        let label = format!("{:<9}", f.label.chars().take(9).collect::<String>());
        let (text, style, mark) = match (&app.mode, here) {
            (Mode::Editing { buffer, error }, true) => {
                let mark = if error.is_some() { " ✗" } else { " ✓" };
                let style = if error.is_some() { st.bad() } else { st.good() };
                (format!("{buffer}▏"), style, mark)
            }
            _ => {
                let text = match f.target {
                    Target::Accuracy => {
                        let a = app.params.accuracy;
                        format!("{a} ({} mm)", a.element_size_mm())
                    }
                    _ => f.text.clone(),
                };
                (text, Style::default(), "")
            }
        };
        let unit = f.unit.trim();
        let mut spans = vec![
            Span::styled(if here { "▶ " } else { "  " }, st.title()),
            Span::styled(label, if here { st.title() } else { Style::default() }),
            Span::styled(text, style),
        ];
        if !unit.is_empty() {
            spans.push(Span::styled(format!(" {unit}"), st.dim()));
        }
        spans.push(Span::styled(mark, style));
        lines.push(Line::from(spans));
    }
    let title = if focused {
        " Parameters (Enter edits) "
    } else {
        " Parameters (Tab) "
    };
    let block =
        Block::bordered()
            .title(title)
            .border_style(if focused { st.title() } else { st.dim() });
    frame.render_widget(Paragraph::new(lines).block(block), area);
}

fn draw_run(frame: &mut Frame, app: &App, area: Rect, st: &Styles) {
    let mut lines: Vec<Line> = Vec::new();
    let title;
    if let Mode::Editing { error, .. } = &app.mode {
        let f = &app.params.fields[app.cursor];
        title = format!(" Editing {} ", f.label);
        match error {
            Some(e) => lines.push(Line::styled(format!("✗ {e}"), st.bad())),
            None => lines.push(Line::styled(
                "✓ valid: Enter keeps it, Esc drops it",
                st.good(),
            )),
        }
        let hint = match f.target {
            Target::Accuracy => "coarse (5 mm), standard (2.5 mm) or fine (1.25 mm)",
            Target::LockingAngle => "the fabric's shear locking angle, °",
            Target::Axis { .. } => "values: 5, 7.5, 10 — or a range: 5..10/3",
        };
        lines.push(Line::styled(hint, st.dim()));
    } else {
        title = " Run ".into();
        let (done, feasible) = app.counts();
        let total = app.entries.len();
        let state = match &app.run {
            RunState::Idle => Line::raw(format!("ready: r runs {total} designs")),
            RunState::Running => {
                Line::raw(format!("running: {done}/{total} done, {feasible} feasible"))
            }
            RunState::Stopping => Line::styled("cancelling…", st.warn()),
            RunState::Finished { wall_s } => Line::styled(
                format!(
                    "finished: {done}/{total} in {}, {feasible} feasible",
                    show_duration(*wall_s)
                ),
                st.good(),
            ),
            RunState::Cancelled { wall_s } => Line::styled(
                format!(
                    "cancelled after {}: {done}/{total} kept (r resumes)",
                    show_duration(*wall_s)
                ),
                st.warn(),
            ),
            RunState::Failed(e) => Line::styled(format!("failed: {e}"), st.bad()),
        };
        lines.push(state);
        let sort = format!(
            "sort: {} {} · {}",
            app.sort_name(app.sort.column),
            if app.sort.descending { "↓" } else { "↑" },
            if app.feasible_only {
                "feasible only"
            } else {
                "all designs"
            }
        );
        lines.push(Line::styled(sort, st.dim()));
        let fabric = &app.table_plan.base_scene.fabric;
        lines.push(Line::styled(
            format!(
                "limits: shear {}°, tension {} N",
                show_value(&toml::Value::Float(fabric.locking_angle_deg)),
                show_value(&toml::Value::Float(fabric.break_tension_n))
            ),
            st.dim(),
        ));
        if app.edited() {
            lines.push(Line::styled(
                format!("edited: r runs the new {} designs", app.params.plan.len()),
                st.warn(),
            ));
        }
        if !app.status.is_empty() {
            lines.push(Line::raw(app.status.clone()));
        }
    }
    let block = Block::bordered().title(title).border_style(st.dim());
    frame.render_widget(
        Paragraph::new(lines).wrap(Wrap { trim: true }).block(block),
        area,
    );
}

fn draw_table(frame: &mut Frame, app: &App, area: Rect, st: &Styles) {
    let visible = app.visible();
    let params = app.table_plan.columns();
    let locking = app.table_plan.base_scene.fabric.locking_angle_deg;
    let breaking = app.table_plan.base_scene.fabric.break_tension_n;
    let err = app.params.accuracy.error().max_shear_deg;
    let sorted = |i: usize, name: &str| {
        if app.sort.column == i {
            format!("{name}{}", if app.sort.descending { "↓" } else { "↑" })
        } else {
            name.to_string()
        }
    };
    let short = |name: &str| match name {
        "friction" => "μ".to_string(),
        "holder_pressure" => "p MPa".to_string(),
        n => n.rsplit('.').next().unwrap_or(n).to_string(),
    };
    let p = params.len();
    let mut header = vec![sorted(0, "#")];
    header.extend(
        params
            .iter()
            .enumerate()
            .map(|(i, c)| sorted(i + 1, &short(&c.name))),
    );
    for (k, name) in ["shear°", "T N", "F kN", "verdict", "s"].iter().enumerate() {
        header.push(sorted(p + 1 + k, name));
    }
    header.push("±°".into());
    let mut widths = vec![Constraint::Length(3)];
    widths.extend(params.iter().map(|c| {
        Constraint::Length(match c.name.as_str() {
            "friction" => 5,
            "holder_pressure" => 5,
            _ => 4,
        })
    }));
    widths.extend([
        Constraint::Length(6),
        Constraint::Length(5),
        Constraint::Length(5),
        Constraint::Length(10),
        Constraint::Length(5),
        Constraint::Length(4),
    ]);
    let rows: Vec<TableRow> = visible
        .iter()
        .map(|&i| {
            let e: &Entry = &app.entries[i];
            let r = e.row.as_ref();
            let mut cells = vec![Cell::from(format!("{}", e.design.index))];
            cells.extend(e.params.iter().map(|(_, v)| Cell::from(show_value(v))));
            let shear = r.and_then(|r| r.max_shear_deg);
            let tension = r.and_then(|r| r.max_tension_n);
            let over = |v: Option<f64>, limit: f64| {
                if v.is_some_and(|v| v > limit) {
                    st.bad()
                } else {
                    Style::default()
                }
            };
            cells.push(Cell::from(fixed(shear, 1)).style(over(shear, locking)));
            cells.push(Cell::from(fixed(tension, 0)).style(over(tension, breaking)));
            cells.push(Cell::from(fixed(
                r.and_then(|r| r.punch_force_n).map(|f| f / 1000.0),
                2,
            )));
            let (word, style) = verdict_cell(r, app, st);
            cells.push(Cell::from(word).style(style));
            cells.push(Cell::from(fixed(r.and_then(|r| r.wall_s), 1)));
            cells.push(Cell::from(if shear.is_some() {
                format!("{err:.1}")
            } else {
                String::new()
            }));
            TableRow::new(cells)
        })
        .collect();
    let focused = app.focus == Focus::Results;
    let title = format!(
        " Results: {} of {} designs{} ",
        visible.len(),
        app.entries.len(),
        if app.feasible_only {
            ", feasible only"
        } else {
            ""
        }
    );
    let block =
        Block::bordered()
            .title(title)
            .border_style(if focused { st.title() } else { st.dim() });
    let table = Table::new(rows, widths)
        .header(TableRow::new(header).style(st.title()))
        .column_spacing(1)
        .block(block)
        .row_highlight_style(if focused { st.selected() } else { st.dim() });
    let mut state = TableState::default();
    if !visible.is_empty() {
        state.select(Some(app.selected.min(visible.len() - 1)));
    }
    frame.render_stateful_widget(table, area, &mut state);
}

/// The colour bar: the scale from 0 to `top`, the locking angle marked.
fn scale_line<'a>(width: u16, locking: f64, top: f64, st: &Styles) -> Vec<Line<'a>> {
    let w = width.max(10) as usize;
    let mut bar = Vec::new();
    let mark = ((locking / top) * (w - 1) as f64).round() as usize;
    for i in 0..w {
        let v = top * i as f64 / (w - 1) as f64;
        if st.colour {
            bar.push(Span::styled("█", Style::default().fg(colour(v, locking))));
        } else {
            bar.push(Span::raw(super::shear_map::shade(v, locking).to_string()));
        }
    }
    let mut marks = vec![' '; w];
    marks[mark.min(w - 1)] = '▲';
    let mut labels: Vec<char> = vec![' '; w];
    let put = |labels: &mut Vec<char>, at: usize, text: &str| {
        let at = at.min(w.saturating_sub(text.chars().count()));
        for (k, ch) in text.chars().enumerate() {
            if at + k < w {
                labels[at + k] = ch;
            }
        }
    };
    put(&mut labels, 0, "0°");
    let lock = format!("{locking:.0}° locking");
    put(
        &mut labels,
        mark.saturating_sub(lock.chars().count() / 2),
        &lock,
    );
    let topl = format!("{top:.0}°");
    if mark + lock.chars().count() / 2 + 2 + topl.len() < w {
        put(&mut labels, w - topl.len(), &topl);
    }
    vec![
        Line::from(bar),
        Line::raw(marks.into_iter().collect::<String>()),
        Line::raw(labels.into_iter().collect::<String>()),
    ]
}

fn draw_detail(frame: &mut Frame, app: &mut App, area: Rect, st: &Styles) {
    let block = Block::bordered()
        .title(" Detail (Enter / Esc) ")
        .border_style(st.dim());
    let inner = block.inner(area);
    frame.render_widget(block, area);
    let Some(entry) = app.selected_entry().cloned() else {
        frame.render_widget(Paragraph::new("no design selected"), inner);
        return;
    };
    let plan = &app.table_plan;
    let locking = plan.base_scene.fabric.locking_angle_deg;
    let breaking = plan.base_scene.fabric.break_tension_n;
    let accuracy = app.params.accuracy;
    let err = accuracy.error();
    let mut lines = vec![Line::styled(
        format!(
            "design {} · {}",
            entry.design.index,
            plan.label_lines(&entry.design).join(" · ")
        ),
        st.title(),
    )];
    match entry.row.as_ref() {
        None => lines.push(Line::styled(
            if app.running() {
                "not finished yet"
            } else {
                "not run: r runs the sweep"
            },
            st.dim(),
        )),
        Some(r) => {
            let (word, style) = verdict_cell(Some(r), app, st);
            let mut verdict = vec![Span::styled(word, style)];
            if let Some(f) = &r.failure {
                verdict.push(Span::raw(format!(": {f}")));
            }
            lines.push(Line::from(verdict));
            if let Some(s) = r.max_shear_deg {
                lines.push(Line::from(vec![
                    Span::raw("max shear "),
                    Span::styled(
                        format!("{s:.1}°"),
                        if s > locking { st.bad() } else { st.good() },
                    ),
                    Span::raw(format!(" ±{:.1}° (locking {locking}°)", err.max_shear_deg)),
                ]));
            }
            if let Some(t) = r.max_tension_n {
                lines.push(Line::from(vec![
                    Span::raw("max yarn tension "),
                    Span::styled(
                        format!("{t:.0} N"),
                        if t > breaking { st.bad() } else { st.good() },
                    ),
                    Span::raw(format!(" (break {breaking} N)")),
                ]));
            }
            if let Some(f) = r.punch_force_n {
                lines.push(Line::raw(format!(
                    "punch force {:.2} kN ±{:.1} %",
                    f / 1000.0,
                    err.punch_force_pct
                )));
            }
            if let Some(w) = r.wall_s {
                lines.push(Line::raw(format!(
                    "run time {w:.1} s at {accuracy} ({} mm elements)",
                    accuracy.element_size_mm()
                )));
            }
        }
    }
    let text_height = lines.len() as u16;
    let field: Option<StoredField> = match app.selected_field() {
        Some(Ok(f)) => Some(f.clone()),
        Some(Err(e)) => {
            lines.push(Line::styled(format!("no map: {e}"), st.warn()));
            None
        }
        None => None,
    };
    // Beside the figures when the pane is wide and low (the full screen of a small terminal),
    // under them otherwise.
    let [text_area, map_area] = if inner.width > 3 * inner.height {
        let [map, text] = Layout::horizontal([Constraint::Percentage(55), Constraint::Min(20)])
            .spacing(2)
            .areas(inner);
        [text, map]
    } else {
        Layout::vertical([Constraint::Length(text_height + 1), Constraint::Min(0)]).areas(inner)
    };
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), text_area);
    let Some(field) = field else { return };
    if map_area.height < 5 {
        return;
    }
    let [map, bar] = Layout::vertical([Constraint::Min(2), Constraint::Length(3)]).areas(map_area);
    let (quads, values) = crate::report::sweep::full_blank(&field);
    let top = values.iter().copied().fold(1.1 * locking, f64::max);
    let max_at = field
        .max_at
        .map(|p| format!(" at ({:.0}, {:.0}) mm", p[0], p[1]))
        .unwrap_or_default();
    let caption = format!("shear, max {:.1}°{max_at}", field.max_shear_deg);
    let [caption_area, map] =
        Layout::vertical([Constraint::Length(1), Constraint::Min(1)]).areas(map);
    frame.render_widget(
        Paragraph::new(Line::styled(caption, st.dim())),
        caption_area,
    );
    frame.render_widget(
        ShearMap {
            quads: &quads,
            shear_deg: &values,
            locking_angle_deg: locking,
            scale_max: top,
            colour: app.colour,
        },
        map,
    );
    frame.render_widget(Paragraph::new(scale_line(bar.width, locking, top, st)), bar);
}

fn draw_gauge(frame: &mut Frame, app: &App, area: Rect, st: &Styles) {
    let total = app.to_run.max(app.done).max(1);
    let ratio = if app.running() || app.done > 0 {
        (app.done as f64 / total as f64).min(1.0)
    } else {
        0.0
    };
    let eta = app
        .eta_s()
        .map(|s| format!(", ETA {}", show_duration(s)))
        .unwrap_or_default();
    let elapsed = if app.running() {
        format!(", {} elapsed", show_duration(app.now_s - app.run_started_s))
    } else {
        String::new()
    };
    let label = if app.run == RunState::Idle {
        "no run yet".to_string()
    } else {
        format!("{}/{} designs{elapsed}{eta}", app.done, app.to_run)
    };
    let gauge = Gauge::default()
        .ratio(ratio)
        .label(label)
        .use_unicode(true)
        .gauge_style(if st.colour {
            Style::default().fg(Color::Cyan).bg(Color::Black)
        } else {
            Style::default().add_modifier(Modifier::REVERSED)
        });
    frame.render_widget(gauge, area);
}

fn draw_keys(frame: &mut Frame, app: &App, area: Rect, st: &Styles) {
    let keys = match &app.mode {
        Mode::Editing { .. } => "type · Enter keep · Esc drop",
        Mode::Exporting { .. } => "type a folder · Enter export · Esc drop",
        Mode::Detail => "↑↓ design · Esc back · q quit",
        _ if app.running() => "c cancel · s sort · f feasible · Enter detail · ? help · q quit",
        _ => "r run · e export · s sort · f feasible · Tab panel · Enter · ? help · q quit",
    };
    frame.render_widget(
        Paragraph::new(Line::styled(format!(" {keys}"), st.dim())),
        area,
    );
}

/// A rectangle of `w × h` centred in `area` (clipped to it).
fn centred(area: Rect, w: u16, h: u16) -> Rect {
    let w = w.min(area.width);
    let h = h.min(area.height);
    Rect::new(
        area.x + (area.width - w) / 2,
        area.y + (area.height - h) / 2,
        w,
        h,
    )
}

const HELP: &[(&str, &str)] = &[
    (
        "r",
        "run the sweep of the parameters (resumes after a cancel)",
    ),
    ("c, Esc", "cancel: workers stop, finished rows stay"),
    ("e", "export results.csv, maps and report.png to a folder"),
    ("Tab", "move between the parameters and the results"),
    ("↑ ↓ PgUp PgDn", "select a parameter or a design"),
    ("Enter", "edit the parameter / open the design's detail"),
    ("← →", "accuracy level down / up"),
    ("s, S", "sort by the next column, reverse the order"),
    ("f", "show feasible designs only, or all"),
    ("?", "this help"),
    ("q, Ctrl-C", "quit (a running sweep is cancelled)"),
];

fn draw_help(frame: &mut Frame, area: Rect, st: &Styles) {
    let rect = centred(area, 76, HELP.len() as u16 + 6);
    frame.render_widget(Clear, rect);
    let mut lines: Vec<Line> = HELP
        .iter()
        .map(|(k, what)| {
            Line::from(vec![
                Span::styled(format!("{k:>14}  "), st.title()),
                Span::raw(*what),
            ])
        })
        .collect();
    lines.push(Line::raw(""));
    lines.push(Line::styled(
        "Values: 5, 7.5, 10 or a range 5..10/3. Verdict: ✓ feasible, ✗ shear/tension over",
        st.dim(),
    ));
    lines.push(Line::styled(
        "the limit, ! failed to converge, - invalid (breaks a bound). Any key closes.",
        st.dim(),
    ));
    frame.render_widget(
        Paragraph::new(lines).block(Block::bordered().title(" Help ")),
        rect,
    );
}

fn draw_export_prompt(frame: &mut Frame, area: Rect, buffer: &str, st: &Styles) {
    let rect = centred(area, 70, 5);
    frame.render_widget(Clear, rect);
    let lines = vec![
        Line::raw(format!("{buffer}▏")),
        Line::styled(
            "results.csv, results.json, maps/, report.png — as `wovenform sweep` writes",
            st.dim(),
        ),
    ];
    frame.render_widget(
        Paragraph::new(lines).block(Block::bordered().title(" Export to folder (Enter) ")),
        rect,
    );
}
