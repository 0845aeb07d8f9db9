//! The detail of a design: its verdict and reason, its figures with their error estimates,
//! and its shear map in half blocks with the colour bar and the locking angle. Beside the
//! table from 130 columns, over the whole screen below that.

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Paragraph, Widget, Wrap};

use crate::study::sweep::{Row, StoredField};

use super::app::{App, DetailMap, Entry};
use super::shear_map::{ShearMap, colour, shade};
use super::style::{Styles, verdict_cell};
use crate::accuracy::Accuracy;
use crate::verdict::Limits;

/// The colour bar: the scale from 0 to `top` in `unit`, the limit marked when it lies on it.
fn scale_line<'a>(
    width: u16,
    (limit, limit_name): (f64, &str),
    top: f64,
    unit: &str,
    st: &Styles,
) -> Vec<Line<'a>> {
    let w = width.max(10) as usize;
    let mut bar = Vec::new();
    // The colours run to the limit, or to the top when the limit is off the scale.
    let shown = limit.min(top);
    for i in 0..w {
        let v = top * i as f64 / (w - 1) as f64;
        if st.colour {
            bar.push(Span::styled("█", Style::default().fg(colour(v, shown))));
        } else {
            bar.push(Span::raw(shade(v, shown).to_string()));
        }
    }
    let mut marks = vec![' '; w];
    let mut labels: Vec<char> = vec![' '; w];
    let put = |labels: &mut Vec<char>, at: usize, text: &str| {
        let at = at.min(w.saturating_sub(text.chars().count()));
        for (k, ch) in text.chars().enumerate() {
            if at + k < w {
                labels[at + k] = ch;
            }
        }
    };
    put(&mut labels, 0, &format!("0{unit}"));
    // Millimetres of wrinkle need decimals; degrees and newtons do not.
    let d = if top < 10.0 { 2 } else { 0 };
    let topl = format!("{top:.d$}{unit}");
    if limit <= top {
        let mark = ((limit / top) * (w - 1) as f64).round() as usize;
        marks[mark.min(w - 1)] = '▲';
        let text = format!("{limit:.d$}{unit} {limit_name}");
        put(
            &mut labels,
            mark.saturating_sub(text.chars().count() / 2),
            &text,
        );
        if mark + text.chars().count() / 2 + 2 + topl.len() < w {
            put(&mut labels, w - topl.len(), &topl);
        }
    } else {
        let text = format!("{topl} · {limit_name} {limit:.d$}{unit} is off the scale");
        put(&mut labels, w.saturating_sub(text.chars().count()), &text);
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
    let map_area = super::frontier::split_chart(app, entry, map_area, buf, st);
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
    let Limits {
        locking_angle_deg: locking,
        break_tension_n: breaking,
        ..
    } = entry.limits;
    let accuracy = entry.accuracy.unwrap_or_else(|| {
        Accuracy::of_element_size(app.table_plan.base_scene.mesh.element_size)
            .unwrap_or(app.params.accuracy)
    });
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
    lines.extend(wrinkle_line(r, entry.limits.wrinkle_limit_mm, st));
    if let Some(f) = r.punch_force_n {
        lines.push(Line::raw(format!(
            "punch force {:.2} kN ±{force_err:.1} %",
            f / 1000.0
        )));
    }
    if let Some(Ok(f)) = app.selected_field() {
        lines.push(Line::raw(format!(
            "draw-in {:.1} mm · {:.1} % of the blank over {}°",
            f.draw_in_mm, f.area_over_limit_pct, f.locking_angle_deg
        )));
    }
    lines.extend(cost_lines(r, accuracy, st));
    lines.push(files_line(app, entry, st));
    lines
}

/// What the design's run cost: its run time at its level, and its load steps and Newton
/// iterations where the row carries them.
fn cost_lines<'a>(r: &Row, accuracy: Accuracy, st: &Styles) -> Vec<Line<'a>> {
    let mut lines = Vec::new();
    if let Some(w) = r.wall_s {
        lines.push(Line::raw(format!(
            "run time {w:.1} s at {accuracy} ({} mm elements)",
            accuracy.element_size_mm()
        )));
    }
    if let (Some(steps), Some(newton)) = (r.steps, r.newton_iterations) {
        lines.push(Line::styled(
            format!("{steps} load steps, {newton} Newton iterations"),
            st.dim(),
        ));
    }
    lines
}

/// The wrinkle amplitude with its error and limit, where the design has one (bending).
fn wrinkle_line<'a>(r: &Row, limit: f64, st: &Styles) -> Option<Line<'a>> {
    let w = r.max_wrinkle_mm?;
    let err = r.max_wrinkle_err_mm.unwrap_or(0.0);
    Some(Line::from(vec![
        Span::raw("wrinkles "),
        Span::styled(
            format!("{w:.2} mm"),
            if w > limit { st.bad() } else { st.good() },
        ),
        Span::raw(format!(" ±{err:.2} mm (limit {limit} mm)")),
    ]))
}

/// Where the design's own files are, or how to get them.
fn files_line<'a>(app: &App, entry: &Entry, st: &Styles) -> Line<'a> {
    let about = entry
        .row
        .as_ref()
        .and_then(|r| r.wall_s)
        .map(|w| format!(", a run of about {w:.0} s"))
        .unwrap_or_default();
    match app.design_files.get(&entry.design.id) {
        Some(Ok(files)) if files.is_empty() => {
            Line::styled(format!("writing its PNG maps and VTU{about}…"), st.dim())
        }
        Some(Ok(files)) => {
            let dir = files
                .first()
                .and_then(|f| f.parent())
                .map(|d| d.display().to_string())
                .unwrap_or_default();
            let names: Vec<String> = files
                .iter()
                .filter_map(|f| f.file_name())
                .map(|f| f.to_string_lossy().into_owned())
                .collect();
            Line::raw(format!("files in {dir}: {}", names.join(", ")))
        }
        Some(Err(e)) => Line::styled(format!("files not written: {e}"), st.warn()),
        None => Line::styled(
            format!("+ runs it finer · w writes its PNG maps and VTU{about}"),
            st.dim(),
        ),
    }
}

/// The design's shear (or yarn tension) map, its caption and the colour bar.
fn render_field(app: &App, field: &StoredField, area: Rect, buf: &mut Buffer, st: &Styles) {
    let tension = app.detail_map == DetailMap::Tension && !field.tension_n.is_empty();
    let wrinkles = app.detail_map == DetailMap::Wrinkles && !field.wrinkle_mm.is_empty();
    let [map, bar] = Layout::vertical([Constraint::Min(2), Constraint::Length(3)]).areas(area);
    let max_at = field
        .max_at
        .map(|p| format!(" at ({:.0}, {:.0}) mm", p[0], p[1]))
        .unwrap_or_default();
    let (quads, values, limit, top, caption, unit, limit_name);
    if wrinkles {
        let (q, v) = crate::report::sweep::full_blank_of(field, &field.wrinkle_mm);
        let largest = v.iter().copied().fold(0.0, f64::max);
        limit = field.wrinkle_limit_mm;
        top = if largest >= limit {
            1.1 * largest
        } else {
            limit.max(1e-3)
        };
        caption = format!(
            "wrinkles, peak to valley {:.2} mm (limit {} mm)",
            field.max_wrinkle_mm.unwrap_or(largest),
            limit
        );
        (quads, values, unit, limit_name) = (q, v, " mm", "limit");
    } else if tension {
        let (q, v) = crate::report::sweep::full_blank_of(field, &field.tension_n);
        let largest = v.iter().copied().fold(0.0, f64::max);
        limit = field.break_tension_n;
        // Scaled to the field (a blank at a fifth of the break is not pale all over).
        top = if largest >= limit {
            1.1 * largest
        } else {
            largest.max(1.0)
        };
        caption = format!(
            "yarn tension, cell peak {:.0} N (break {:.0} N)",
            field.max_tension_n, limit
        );
        (quads, values, unit, limit_name) = (q, v, " N", "break");
    } else {
        let (q, v) = crate::report::sweep::full_blank(field);
        limit = field.locking_angle_deg;
        top = v.iter().copied().fold(1.1 * limit, f64::max);
        let asked = if app.detail_map == DetailMap::Wrinkles {
            " (no wrinkle map: the scene has no bending, fabric.bending_rigidity)"
        } else {
            ""
        };
        caption = format!(
            "shear, cell peak {:.1}°{max_at}{asked}",
            field.max_shear_deg
        );
        (quads, values, unit, limit_name) = (q, v, "°", "locking");
    }
    let [caption_area, map] =
        Layout::vertical([Constraint::Length(1), Constraint::Min(1)]).areas(map);
    Paragraph::new(Line::styled(caption, st.dim())).render(caption_area, buf);
    ShearMap {
        quads: &quads,
        shear_deg: &values,
        locking_angle_deg: limit.min(top),
        scale_max: top,
        colour: app.colour,
    }
    .render(map, buf);
    Paragraph::new(scale_line(bar.width, (limit, limit_name), top, unit, st)).render(bar, buf);
}
