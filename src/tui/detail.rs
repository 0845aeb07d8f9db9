//! The detail of a design: its verdict and reason, its figures with their error estimates,
//! and its shear map in half blocks with the colour bar and the locking angle. Beside the
//! table from 130 columns, over the whole screen below that.

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Paragraph, Widget, Wrap};

use crate::study::sweep::StoredField;

use super::app::{App, Entry};
use super::shear_map::{ShearMap, colour, shade};
use super::view::{Styles, verdict_cell};
use crate::accuracy::Accuracy;

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
            bar.push(Span::raw(shade(v, locking).to_string()));
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

/// The selected design's detail: its verdict and figures, and its shear map with the colour
/// bar (the field read when the design was selected).
pub(super) fn render_detail(app: &App, area: Rect, buf: &mut Buffer, st: &Styles) {
    let block = Block::bordered()
        .title(" Detail (Enter / Esc) ")
        .border_style(st.dim());
    let inner = block.inner(area);
    block.render(area, buf);
    let Some(entry) = app.selected_entry() else {
        Paragraph::new("no design selected").render(inner, buf);
        return;
    };
    let mut lines = figure_lines(app, entry, st);
    let text_height = lines.len() as u16;
    let field: Option<&StoredField> = match app.selected_field() {
        Some(Ok(f)) => Some(f),
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
    Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .render(text_area, buf);
    if let Some(field) = field
        && map_area.height >= 5
    {
        render_field(app, field, map_area, buf, st);
    }
}

/// The design's label, verdict and figures with their errors and limits.
fn figure_lines<'a>(app: &App, entry: &Entry, st: &Styles) -> Vec<Line<'a>> {
    let plan = &app.table_plan;
    let mut lines = vec![Line::styled(
        format!(
            "design {} · {}",
            entry.design.index,
            plan.label_lines(&entry.design).join(" · ")
        ),
        st.title(),
    )];
    let Some(r) = entry.row.as_ref() else {
        let why = if app.running() {
            "not finished yet"
        } else {
            "not run: r runs the sweep"
        };
        lines.push(Line::styled(why, st.dim()));
        return lines;
    };
    let [locking, breaking] = entry.limits;
    let accuracy = Accuracy::of_element_size(app.table_plan.base_scene.mesh.element_size)
        .unwrap_or(app.params.accuracy);
    let level = accuracy.error();
    let shear_err = r.max_shear_err_deg.unwrap_or(level.max_shear_deg);
    let tension_err = r.max_tension_err_pct.unwrap_or(level.max_tension_pct);
    let force_err = r.punch_force_err_pct.unwrap_or(level.punch_force_pct);
    let (word, style) = verdict_cell(entry, app, st);
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
            Span::raw(format!(" ±{shear_err:.1}° (locking {locking}°)")),
        ]));
    }
    if let Some(t) = r.max_tension_n {
        lines.push(Line::from(vec![
            Span::raw("max yarn tension "),
            Span::styled(
                format!("{t:.0} N"),
                if t > breaking { st.bad() } else { st.good() },
            ),
            Span::raw(format!(" ±{tension_err:.0} % (break {breaking} N)")),
        ]));
    }
    if let Some(f) = r.punch_force_n {
        lines.push(Line::raw(format!(
            "punch force {:.2} kN ±{force_err:.1} %",
            f / 1000.0
        )));
    }
    if let Some(w) = r.wall_s {
        lines.push(Line::raw(format!(
            "run time {w:.1} s at {accuracy} ({} mm elements)",
            accuracy.element_size_mm()
        )));
    }
    lines
}

/// The design's shear map, its caption and the colour bar.
fn render_field(app: &App, field: &StoredField, area: Rect, buf: &mut Buffer, st: &Styles) {
    let locking = field.locking_angle_deg;
    let [map, bar] = Layout::vertical([Constraint::Min(2), Constraint::Length(3)]).areas(area);
    let (quads, values) = crate::report::sweep::full_blank(field);
    let top = values.iter().copied().fold(1.1 * locking, f64::max);
    let max_at = field
        .max_at
        .map(|p| format!(" at ({:.0}, {:.0}) mm", p[0], p[1]))
        .unwrap_or_default();
    let caption = format!("shear, max {:.1}°{max_at}", field.max_shear_deg);
    let [caption_area, map] =
        Layout::vertical([Constraint::Length(1), Constraint::Min(1)]).areas(map);
    Paragraph::new(Line::styled(caption, st.dim())).render(caption_area, buf);
    ShearMap {
        quads: &quads,
        shear_deg: &values,
        locking_angle_deg: locking,
        scale_max: top,
        colour: app.colour,
    }
    .render(map, buf);
    Paragraph::new(scale_line(bar.width, locking, top, st)).render(bar, buf);
}
