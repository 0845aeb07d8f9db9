//! Drawing the explorer: the parameters, the run, the results table, the detail of a design
//! (`detail`), the progress gauge and the keys; a help window over it on `?`. The explorer is
//! a widget, `impl Widget for &App`: drawing reads the state and nothing else (no files).
//!
//! 80 × 24 and up. From 130 columns the detail pane sits beside the table; below that, Enter
//! opens it over the whole screen.

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{
    Block, Cell, Clear, Gauge, Paragraph, Row as TableRow, StatefulWidget, Table, TableState,
    Widget, Wrap,
};

use crate::study::sweep::show_value;
use crate::verdict::Limits;

use super::app::{App, Entry, Focus, Mode, RunState};
use super::detail::render_detail;
use super::params::Target;
use super::style::{Styles, verdict_cell};

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

fn fixed(v: Option<f64>, decimals: usize) -> String {
    v.map(|v| crate::show::Fixed(v, decimals).to_string())
        .unwrap_or_default()
}

/// The whole explorer: `frame.render_widget(&app, frame.area())`.
impl Widget for &App {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let app = self;
        let st = Styles { colour: app.colour };
        let [title, main, gauge, keys] = Layout::vertical([
            Constraint::Length(1),
            Constraint::Min(8),
            Constraint::Length(1),
            Constraint::Length(1),
        ])
        .areas(area);
        render_title(app, title, buf, &st);
        if app.mode == Mode::Detail {
            render_detail(app, main, buf, &st);
        } else {
            let top_height =
                (app.params.fields.len() as u16 + 2).min(main.height.saturating_sub(5));
            let [top, bottom] =
                Layout::vertical([Constraint::Length(top_height), Constraint::Min(3)]).areas(main);
            let [params, run] =
                Layout::horizontal([Constraint::Percentage(55), Constraint::Percentage(45)])
                    .areas(top);
            render_parameters(app, params, buf, &st);
            render_run(app, run, buf, &st);
            if area.width >= WIDE {
                // The wrinkle column (6 and a space) widens the table where the fabric bends.
                let table_w = if app.bends() { 91 } else { 84 };
                let [table, detail] =
                    Layout::horizontal([Constraint::Length(table_w), Constraint::Min(40)])
                        .areas(bottom);
                render_table(app, table, buf, &st);
                render_detail(app, detail, buf, &st);
            } else {
                render_table(app, bottom, buf, &st);
            }
        }
        render_gauge(app, gauge, buf, &st);
        render_keys(app, keys, buf, &st);
        match &app.mode {
            Mode::Help => render_help(area, buf, &st),
            Mode::Exporting { buffer } => render_export_prompt(area, buf, buffer, &st),
            _ => {}
        }
    }
}

fn render_title(app: &App, area: Rect, buf: &mut Buffer, st: &Styles) {
    let p = &app.params;
    let err = p.accuracy.error();
    let fabric = &p.plan.base_scene.fabric;
    let shear = match (fabric.shear_moment, fabric.shear_locking) {
        (Some(_), true) => " · shear law, stiffening past locking",
        (Some(_), false) => " · shear law",
        (None, _) => "",
    };
    let text = format!(
        " wovenform · {} · {} designs · {} ±{:.1}° · locking {}°{shear}",
        p.source.title,
        p.plan.len(),
        p.accuracy,
        err.max_shear_deg,
        crate::show::Num(p.limits.locking_angle_deg),
    );
    Paragraph::new(Line::styled(text, st.title())).render(area, buf);
}

fn render_parameters(app: &App, area: Rect, buf: &mut Buffer, st: &Styles) {
    let focused = app.focus == Focus::Parameters;
    let mut lines = Vec::new();
    let label_width = app
        .params
        .fields
        .iter()
        .map(|f| f.label.chars().count())
        .max()
        .unwrap_or(8);
    for (i, f) in app.params.fields.iter().enumerate() {
        let here = focused && i == app.cursor;
        let label = format!("{:<w$}", f.label, w = label_width + 1);
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
    Paragraph::new(lines).block(block).render(area, buf);
}

fn render_run(app: &App, area: Rect, buf: &mut Buffer, st: &Styles) {
    let (title, lines) = match &app.mode {
        Mode::Editing { error, .. } => editing_lines(app, error.as_ref(), st),
        _ => (" Run ".to_string(), run_lines(app, st)),
    };
    let block = Block::bordered().title(title).border_style(st.dim());
    Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .block(block)
        .render(area, buf);
}

/// The Run panel while a parameter is edited: its title, whether the text is valid, a hint.
fn editing_lines<'a>(
    app: &App,
    error: Option<&super::error::ParamError>,
    st: &Styles,
) -> (String, Vec<Line<'a>>) {
    let mut lines: Vec<Line> = Vec::new();
    let f = &app.params.fields[app.cursor];
    let title = format!(" Editing {} ", f.label);
    match error {
        Some(e) => lines.push(Line::styled(format!("✗ {e}"), st.bad())),
        None => lines.push(Line::styled(
            "✓ valid: Enter keeps it, Esc drops it",
            st.good(),
        )),
    }
    let hint = match &f.target {
        Target::Accuracy => "coarse (5 mm), standard (2.5 mm) or fine (1.25 mm)",
        Target::LockingAngle => "the fabric's shear locking angle, °",
        Target::BreakTension => "the yarns' break tension, N",
        Target::Axis { key, .. } => axis_hint(key.as_str()),
    };
    lines.push(Line::styled(hint, st.dim()));
    (title, lines)
}

/// Where the run is, in one line.
fn state_line<'a>(app: &App, st: &Styles) -> Line<'a> {
    let (done, feasible) = app.counts();
    let total = app.entries.len();
    match &app.run {
        RunState::Idle => {
            // A rough figure (the mesh and the stroke), one core a design.
            let each = crate::study::estimate::run_seconds(&app.params.plan.base_scene);
            Line::raw(format!(
                "ready: r runs {total} designs, about {} each",
                show_duration(each.max(1.0))
            ))
        }
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
    }
}

/// The Run panel: where the run is, the sort, the limits, what was edited, the status.
fn run_lines<'a>(app: &App, st: &Styles) -> Vec<Line<'a>> {
    let mut lines: Vec<Line> = vec![state_line(app, st)];
    lines.extend(super::frontier::run_line(app, st));
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
    let limits = Limits::of(&app.table_plan.base_scene);
    // The wrinkle limit where the fabric bends (the paper's membrane has no wrinkles).
    let bends = app.table_plan.base_scene.fabric.bending_rigidity.is_some();
    let wrinkles = if bends {
        let w = crate::show::Num(limits.wrinkle_limit_mm);
        format!(", wrinkles {w} mm")
    } else {
        String::new()
    };
    lines.push(Line::styled(
        format!(
            "limits: shear {}°, tension {} N{wrinkles}",
            crate::show::Num(limits.locking_angle_deg),
            crate::show::Num(limits.break_tension_n)
        ),
        st.dim(),
    ));
    if app.edited() {
        lines.push(Line::styled(
            format!("edited: r runs the new {} designs", app.params.plan.len()),
            st.warn(),
        ));
    }
    let marginal = app.marginal_ids().len();
    if marginal > 0 && !app.running() {
        lines.push(Line::styled(
            format!("≈ {marginal} marginal: m re-runs them one level finer"),
            st.warn(),
        ));
    }
    if let Some(status) = app.fresh_status() {
        lines.push(Line::raw(status.to_string()));
    }
    lines
}

fn render_table(app: &App, area: Rect, buf: &mut Buffer, st: &Styles) {
    let area = super::frontier::split_boundaries(app, area, buf, st);
    let visible = app.visible();
    let (header, widths) = table_header(app);
    let rows: Vec<TableRow> = visible
        .iter()
        .map(|&i| table_row(app, &app.entries[i], st))
        .collect();
    let focused = app.focus == Focus::Results;
    let paper = app.entries.iter().any(is_paper_design);
    let title = format!(
        " Results: {} of {} designs{}{} ",
        visible.len(),
        app.entries.len(),
        if app.feasible_only {
            ", feasible only"
        } else {
            ""
        },
        if paper {
            " · ★ the paper's designs"
        } else {
            ""
        }
    );
    let title = match app
        .table_plan
        .columns()
        .iter()
        .any(|c| c.name == "holder_pressure")
    {
        true if area.width as usize > title.chars().count() + 28 => {
            format!("{title}· p holder pressure ")
        }
        _ => title,
    };
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
    StatefulWidget::render(table, area, buf, &mut state);
}

/// The table's header (the sorted column marked ↑ or ↓) and column widths.
fn table_header(app: &App) -> (Vec<String>, Vec<Constraint>) {
    let params = app.table_plan.columns();
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
        "r" | "rp" | "rm" => format!("{name} mm"),
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
    if app.bends() {
        // After the force: the wrinkles, sorted as the last figure.
        header.insert(p + 4, sorted(p + 6, "wr mm"));
    }
    // The design numbers in full (1999 and 1998 are not both "199"), and the sort mark.
    let digits = app.entries.len().saturating_sub(1).max(1).to_string().len() as u16;
    let mut widths = vec![Constraint::Length(digits.max(2) + 1)];
    widths.extend(
        params
            .iter()
            .map(|c| Constraint::Length(param_width(&c.name) as u16)),
    );
    widths.extend([
        Constraint::Length(6),
        Constraint::Length(5),
        Constraint::Length(5),
        Constraint::Length(10),
        Constraint::Length(5),
        Constraint::Length(4),
    ]);
    if app.bends() {
        widths.insert(p + 4, Constraint::Length(6));
    }
    (header, widths)
}

/// An example of values for a swept key, in its units.
fn axis_hint(key: &str) -> &'static str {
    match key {
        "process.friction" => "values: 0.1, 0.2, 0.3 — or a range: 0.1..0.3/3",
        "process.holder_pressure" => "values (MPa): 0.5, 1, 2 — or a range: 0.5..2/4",
        k if k.starts_with("tools.") => "values (mm): 5, 7.5, 10 — or a range: 5..10/3",
        _ => "values: 1, 2, 3 — or a range: 1..3/3",
    }
}

/// One of the paper's two box designs (Figure 11): r/rp/rm = 5/6/5 (tight) or 10/15/10 mm
/// (open).
fn is_paper_design(e: &Entry) -> bool {
    let value = |name: &str| {
        e.params
            .iter()
            .find(|(n, _)| n == name)
            .and_then(|(_, v)| crate::study::sweep::as_number(v))
    };
    match (value("r"), value("rp"), value("rm")) {
        (Some(r), Some(rp), Some(rm)) => {
            [[5.0, 6.0, 5.0], [10.0, 15.0, 10.0]].contains(&[r, rp, rm])
        }
        _ => false,
    }
}

/// The width of a parameter's column, characters: its header with units and the sort mark.
fn param_width(name: &str) -> usize {
    match name {
        "r" | "friction" => 5,
        "rp" | "rm" | "holder_pressure" => 6,
        _ => 4,
    }
}

/// A value in `width` characters: a number rounded (0.2158 → "0.216" in five), not cut.
fn fit_value(v: &toml::Value, width: usize) -> String {
    let shown = show_value(v);
    let Some(x) = crate::study::sweep::as_number(v) else {
        return shown;
    };
    if shown.chars().count() <= width {
        return shown;
    }
    (0..=6)
        .rev()
        .map(|d| {
            let t = format!("{x:.d$}");
            if t.contains('.') {
                t.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                t
            }
        })
        .find(|t| t.chars().count() <= width)
        .unwrap_or(shown)
}

/// One design's row: its values, figures (over a limit in red), verdict, run time and error.
fn table_row<'a>(app: &App, e: &Entry, st: &Styles) -> TableRow<'a> {
    let Limits {
        locking_angle_deg: locking,
        break_tension_n: breaking,
        ..
    } = e.limits;
    let r = e.row.as_ref();
    let err = r
        .and_then(|r| r.max_shear_err_deg)
        .unwrap_or(app.params.accuracy.error().max_shear_deg);
    let mark = if is_paper_design(e) { "★" } else { "" };
    let mut cells = vec![Cell::from(format!("{}{mark}", e.design.index))];
    cells.extend(
        e.params
            .iter()
            .map(|(name, v)| Cell::from(fit_value(v, param_width(name)))),
    );
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
    if app.bends() {
        let wrinkle = r.and_then(|r| r.max_wrinkle_mm);
        cells.push(Cell::from(fixed(wrinkle, 2)).style(over(wrinkle, e.limits.wrinkle_limit_mm)));
    }
    let (word, style) = verdict_cell(e, app, st);
    cells.push(Cell::from(word).style(style));
    cells.push(Cell::from(fixed(r.and_then(|r| r.wall_s), 1)));
    cells.push(Cell::from(if shear.is_some() {
        format!("{err:.1}")
    } else {
        String::new()
    }));
    TableRow::new(cells)
}

fn render_gauge(app: &App, area: Rect, buf: &mut Buffer, st: &Styles) {
    // The table's count, as the Run panel says it; a resumed or partial run adds its own.
    let (finished, _) = app.counts();
    let total = app.entries.len().max(1);
    let ratio = (finished as f64 / total as f64).min(1.0);
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
        let this_run = if app.to_run != app.entries.len() {
            format!(" ({}/{} in this run)", app.done, app.to_run)
        } else {
            String::new()
        };
        format!(
            "{finished}/{} designs{this_run}{elapsed}{eta}",
            app.entries.len()
        )
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
    gauge.render(area, buf);
}

fn render_keys(app: &App, area: Rect, buf: &mut Buffer, st: &Styles) {
    let keys = match &app.mode {
        Mode::Editing { .. } => "type · Enter keep · Esc drop",
        Mode::Exporting { .. } => "type a folder · Enter export · Esc drop",
        Mode::Detail => {
            "↑↓ design · t tension · z wrinkles · + finer · w PNG/VTU · Esc back · q quit"
        }
        _ if app.running() => "c cancel · s sort · f feasible · Enter detail · ? help · q quit",
        _ => "r run · b boundary · e export · s sort · f feasible · Enter · ? help · q quit",
    };
    Paragraph::new(Line::styled(format!(" {keys}"), st.dim())).render(area, buf);
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
    ("m", "re-run the marginal designs at the next finer level"),
    ("+", "re-run the selected design at the next finer level"),
    (
        "b",
        "the boundary along the sorted (else first) number column",
    ),
    ("t", "the detail's map: shear or yarn tension"),
    ("w", "write the selected design's PNG maps and VTU"),
    ("e", "export results.csv, maps and report.png to a folder"),
    ("Tab", "move between the parameters and the results"),
    ("↑ ↓ PgUp PgDn", "select a parameter or a design"),
    ("Enter", "edit the parameter / open the design's detail"),
    ("← →", "accuracy level down / up"),
    (
        "s, S · f",
        "sort by the next column, reverse · feasible only / all",
    ),
    ("?", "this help"),
    ("q, Ctrl-C", "quit (a running sweep is cancelled)"),
];

/// What the help says under the keys (wrapped to the box).
const HELP_FOOTER: &str = "Values: 5, 7.5, 10 or a range 5..10/3. Verdicts: ✓ feasible; ≈ marginal (a \
     limit inside the error band: m re-runs it finer); ✗ shear or ✗ tension over its limit; ! \
     failed to converge; - invalid (breaks a bound). Any key closes.";

fn render_help(area: Rect, buf: &mut Buffer, st: &Styles) {
    let width = area.width.min(76);
    let inner = width.saturating_sub(2).max(1) as usize;
    let footer_lines = HELP_FOOTER.chars().count().div_ceil(inner) as u16 + 1;
    let rect = centred(area, width, HELP.len() as u16 + 3 + footer_lines);
    Clear.render(rect, buf);
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
    lines.push(Line::styled(HELP_FOOTER, st.dim()));
    Paragraph::new(lines)
        .wrap(ratatui::widgets::Wrap { trim: false })
        .block(Block::bordered().title(" Help "))
        .render(rect, buf);
}

fn render_export_prompt(area: Rect, buf: &mut Buffer, buffer: &str, st: &Styles) {
    let rect = centred(area, 70, 5);
    Clear.render(rect, buf);
    let lines = vec![
        Line::raw(format!("{buffer}▏")),
        Line::styled(
            "results.csv, results.json, maps/, report.png — as `wovenform sweep` writes",
            st.dim(),
        ),
    ];
    Paragraph::new(lines)
        .block(Block::bordered().title(" Export to folder (Enter) "))
        .render(rect, buf);
}

#[cfg(test)]
mod tests {
    use super::fit_value;
    use toml::Value;

    #[test]
    fn values_are_rounded_to_their_column_not_cut() {
        assert_eq!(fit_value(&Value::Float(0.2158), 5), "0.216");
        assert_eq!(fit_value(&Value::Float(7.5), 4), "7.5");
        assert_eq!(fit_value(&Value::Float(10.46), 4), "10.5");
        assert_eq!(fit_value(&Value::Float(1234.6), 4), "1235");
    }
}
