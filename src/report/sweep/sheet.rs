//! The report sheet of a sweep: the title and base scene, a tile per design, the chart and the
//! ranking.

use super::chart::shear_chart;
use super::full_blank;
use super::table::{RANKED_ON_SHEET, ranked};
use super::window::window_chart;
use crate::report::sheet::{Sheet, Tile, TileMap};
use crate::scene::ToolKind;
use crate::study::sweep::{Design, Plan, Row, StoredField, counts, show_value, unit_of};
use crate::verdict::Verdict;

/// At most this many maps on the report sheet (the first ones in grid order).
pub const SHEET_TILES: usize = 81;

/// The report sheet of a sweep; `field` gives a design's stored field (the caller reads it).
pub fn sheet<E>(
    plan: &Plan,
    rows: &[Row],
    designs: &[Design],
    top: f64,
    field: &dyn Fn(&Row) -> Result<StoredField, E>,
) -> Result<Sheet, E> {
    let (tiles, tiles_note) = tiles(plan, rows, designs, field)?;
    let (chart, chart_note) = match window_chart(plan, rows, designs) {
        Some((chart, note)) => (Some(chart), note),
        None => shear_chart(plan, rows, designs),
    };
    Ok(Sheet {
        title: title(plan, rows),
        subtitle: subtitle(plan, designs),
        tiles,
        tiles_note,
        scale_max: top,
        limit: plan.base_scene.fabric.locking_angle_deg,
        chart,
        chart_note,
        ranking: ranking(plan, rows, designs),
    })
}

/// `Sweep NAME: N designs — 3 ✓ feasible, 5 ✗ infeasible, …`.
fn title(plan: &Plan, rows: &[Row]) -> String {
    let c = counts(rows);
    let mut tally = vec![format!("{} ✓ feasible", c.feasible)];
    if c.marginal > 0 {
        tally.push(format!("{} ≈ marginal", c.marginal));
    }
    tally.push(format!("{} ✗ infeasible", c.infeasible));
    if c.failed > 0 {
        tally.push(format!("{} failed", c.failed));
    }
    if c.invalid > 0 {
        tally.push(format!("{} invalid", c.invalid));
    }
    let missing = plan.len().saturating_sub(rows.len());
    if missing > 0 {
        tally.push(format!("{missing} not computed"));
    }
    format!(
        "Sweep {}: {} design{} — {}",
        plan.name(),
        plan.len(),
        crate::report::plural(plan.len()),
        tally.join(", ")
    )
}

/// The base scene's tools in words, with the die's clearance (a mesh die's is in its STL).
fn tools_line(base: &crate::scene::Scene) -> String {
    let t = &base.tools;
    let tools = match t.kind {
        ToolKind::Box => format!("box punch {} × {} mm", t.side.0[0], t.side.0[1]),
        ToolKind::Ellipsoid => format!(
            "ellipsoid punch {} × {} × {} mm",
            t.axes[0], t.axes[1], t.axes[2]
        ),
        ToolKind::Hemisphere => format!("hemisphere punch, radius {} mm", t.radius),
        ToolKind::Mesh => format!(
            "punch {}, die {} (STL)",
            t.file_name(&t.punch),
            t.file_name(&t.die)
        ),
    };
    // A mesh die's clearance is in its STL.
    if t.kind == ToolKind::Mesh {
        tools
    } else {
        format!("{tools}, clearance {} mm", t.clearance)
    }
}

/// The base scene, what is swept and what is fixed, and what feasible means.
fn subtitle(plan: &Plan, designs: &[Design]) -> Vec<String> {
    let base = &plan.base_scene;
    let tools = tools_line(base);
    let law = if base.fabric.undulation {
        "woven law"
    } else {
        "linear yarn law"
    };
    let swept: Vec<String> = plan
        .axes
        .iter()
        .filter(|a| a.values.len() > 1)
        .map(|a| {
            let vals: Vec<String> = a.values.iter().map(show_value).collect();
            format!("{} ∈ {{{}}}{}", a.column, vals.join(", "), unit_of(&a.key))
        })
        .collect();
    let fixed: Vec<String> = plan
        .columns()
        .iter()
        .filter(|col| col.axis.is_none_or(|a| plan.axes[a].values.len() < 2))
        .map(|col| {
            let v = plan.params(std::slice::from_ref(col), &designs[0]);
            format!("{} {}{}", col.name, show_value(&v[0].1), unit_of(&col.key))
        })
        .collect();
    vec![
        format!(
            "Base scene: {} — {tools}, stroke {} mm, blank {} × {} mm, {law}, mesh {} mm{}; locking angle {}°, break tension {} N",
            plan.base_file.as_deref().unwrap_or(&plan.base_origin),
            base.process.stroke,
            base.blank.size.0[0],
            base.blank.size.0[1],
            base.mesh.element_size,
            match crate::accuracy::Accuracy::of_element_size(base.mesh.element_size) {
                Some(level) => {
                    let e = level.error();
                    format!(
                        " ({level}: max shear ±{}°, force ±{} %, tension ±{} % where radii ≥ 5 mm)",
                        e.max_shear_deg, e.punch_force_pct, e.max_tension_pct
                    )
                }
                None => " (no accuracy level: no error estimate)".into(),
            },
            base.fabric.locking_angle_deg,
            base.fabric.break_tension_n
        ),
        format!(
            "Swept: {}{}",
            if swept.is_empty() {
                "nothing".to_string()
            } else {
                swept.join("; ")
            },
            if fixed.is_empty() {
                String::new()
            } else {
                format!(" — fixed: {}", fixed.join(", "))
            }
        ),
        "Feasible = converged, max shear ≤ locking angle and max yarn tension ≤ break tension (and, with bending, wrinkles ≤ the wrinkle limit) by more than their error; marginal = a limit inside a figure's error band. Every design's map: maps/<design>.png; every row: results.csv.".into(),
    ]
}

/// A tile per design (the first [`SHEET_TILES`] in grid order), and a note when not all are
/// shown.
fn tiles<E>(
    plan: &Plan,
    rows: &[Row],
    designs: &[Design],
    field: &dyn Fn(&Row) -> Result<StoredField, E>,
) -> Result<(Vec<Tile>, Option<String>), E> {
    let missing = plan.len().saturating_sub(rows.len());
    let shown: Vec<&Row> = rows.iter().take(SHEET_TILES).collect();
    let tiles_note = if rows.len() > shown.len() || missing > 0 {
        Some(format!(
            "Showing the first {} of {} designs (grid order){}",
            shown.len(),
            plan.len(),
            if missing > 0 {
                format!("; {missing} designs have no result yet")
            } else {
                String::new()
            }
        ))
    } else {
        None
    };
    let mut tiles = Vec::new();
    for r in shown {
        let map = match &r.map {
            Some(_) => {
                let f = field(r)?;
                let (quads, values) = full_blank(&f);
                Some(TileMap {
                    quads,
                    values,
                    limit: f.locking_angle_deg,
                    die_opening: f.die_opening.clone(),
                })
            }
            None => None,
        };
        tiles.push(Tile {
            id: r.design.clone(),
            lines: plan.label_lines(&designs[r.index]),
            verdict: r.verdict,
            max_shear_deg: if r.converged { r.max_shear_deg } else { None },
            reason: r.failure.clone(),
            map,
        });
    }
    Ok((tiles, tiles_note))
}

/// The ranking beside the tiles: feasible first, then by max shear.
fn ranking(plan: &Plan, rows: &[Row], designs: &[Design]) -> Vec<(Option<Verdict>, String)> {
    let ranked = ranked(rows);
    let mut ranking = vec![(
        None,
        if ranked.len() > RANKED_ON_SHEET {
            format!(
                "The {RANKED_ON_SHEET} best of {} designs (feasible first, then by max shear):",
                rows.len()
            )
        } else {
            "The designs, feasible first, then by max shear:".to_string()
        },
    )];
    for r in ranked.iter().take(RANKED_ON_SHEET) {
        let mut text = format!(
            "{} {}",
            r.verdict.mark(),
            r.design.split('-').next().unwrap_or("")
        );
        let label = plan.label_lines(&designs[r.index]).join("; ");
        if !label.is_empty() {
            text.push_str(&format!("  {label}"));
        }
        match (r.converged, r.max_shear_deg, r.max_tension_n) {
            (true, Some(s), Some(t)) => {
                text.push_str(&format!(" — {s:.1}°, {t:.0} N"));
                if let Some(w) = r.max_wrinkle_mm {
                    text.push_str(&format!(", wrinkles {w:.2} mm"));
                }
            }
            _ => text.push_str(&format!(" — {}", r.verdict.word())),
        }
        ranking.push((Some(r.verdict), text));
    }
    ranking
}
