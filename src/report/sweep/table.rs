//! The feasibility table printed at the end of a sweep, and the ranking it shares with the sheet.

use crate::report::fixed;
use std::fmt::Write as _;

use crate::study::sweep::{Plan, Row, show_value, unit_of};

/// Rows on the sheet's ranking.
pub(super) const RANKED_ON_SHEET: usize = 30;

/// Feasible first, then infeasible, failed, invalid; by max shear within each.
pub fn ranked(rows: &[Row]) -> Vec<&Row> {
    let mut sorted: Vec<&Row> = rows.iter().collect();
    // `Verdict` orders best first.
    sorted.sort_by(|a, b| {
        a.verdict
            .cmp(&b.verdict)
            .then(
                a.max_shear_deg
                    .unwrap_or(f64::INFINITY)
                    .total_cmp(&b.max_shear_deg.unwrap_or(f64::INFINITY)),
            )
            .then(a.index.cmp(&b.index))
    });
    sorted
}

/// The feasibility table printed at the end: feasible designs first, then by max shear;
/// verdicts marked, units in the header.
pub fn table(plan: &Plan, rows: &[Row]) -> String {
    let columns = plan.columns();
    let sorted = ranked(rows);
    let mut head: Vec<(String, String)> =
        vec![("".into(), "".into()), ("design".into(), "".into())];
    for c in &columns {
        head.push((c.name.clone(), unit_of(&c.key).trim().to_string()));
    }
    // The wrinkle column where some design has bending (the paper's membrane has none).
    let wrinkles = rows.iter().any(|r| r.max_wrinkle_mm.is_some());
    let figures = [
        ("max shear", "°"),
        ("max tension", "N"),
        ("punch force", "N"),
        ("wrinkles", "mm"),
        ("wall", "s"),
        ("verdict", ""),
    ];
    for (n, u) in figures
        .into_iter()
        .filter(|(n, _)| wrinkles || *n != "wrinkles")
    {
        head.push((n.into(), u.into()));
    }
    let mut body: Vec<Vec<String>> = Vec::new();
    for r in &sorted {
        let f = |v: Option<f64>, d: usize| v.map(|v| fixed(v, d)).unwrap_or("–".into());
        let mut line = vec![r.verdict.mark().to_string(), r.design.clone()];
        line.extend(r.params.iter().map(|(_, v)| show_value(v)));
        line.push(f(r.max_shear_deg, 1));
        line.push(f(r.max_tension_n, 0));
        line.push(f(r.punch_force_n, 0));
        if wrinkles {
            line.push(f(r.max_wrinkle_mm, 2));
        }
        line.push(f(r.wall_s, 1));
        let mut verdict = r.verdict.word().to_string();
        if let Some(why) = &r.failure {
            let short: String = why.chars().take(90).collect();
            let dots = if why.chars().count() > 90 { "…" } else { "" };
            verdict = format!("{verdict}: {short}{dots}");
        }
        line.push(verdict);
        body.push(line);
    }
    aligned(&head, &body, 2)
}

/// The header's two lines (names, units) and the body, in columns: the first columns (the
/// mark and the design) left-aligned, the parameters and figures right-aligned, the last
/// column (the verdict) as it is.
/// Columns from `numeric_from` on are right-aligned (the table's numbers).
pub fn aligned(head: &[(String, String)], body: &[Vec<String>], numeric_from: usize) -> String {
    let n = head.len();
    let width: Vec<usize> = (0..n)
        .map(|i| {
            let h = head[i].0.chars().count().max(head[i].1.chars().count());
            if i == n - 1 {
                return h;
            }
            body.iter()
                .map(|l| l[i].chars().count())
                .fold(h, usize::max)
        })
        .collect();
    let fmt_line = |cells: Vec<&str>| -> String {
        let mut s = String::new();
        for (i, cell) in cells.iter().enumerate() {
            let pad = width[i].saturating_sub(cell.chars().count());
            if i == n - 1 {
                s.push_str(cell);
            } else if i >= numeric_from {
                s.push_str(&" ".repeat(pad));
                s.push_str(cell);
                s.push_str("  ");
            } else {
                s.push_str(cell);
                s.push_str(&" ".repeat(pad));
                s.push_str("  ");
            }
        }
        s.trim_end().to_string()
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}",
        fmt_line(head.iter().map(|h| h.0.as_str()).collect())
    );
    let _ = writeln!(
        out,
        "{}",
        fmt_line(head.iter().map(|h| h.1.as_str()).collect())
    );
    for line in body {
        let _ = writeln!(
            out,
            "{}",
            fmt_line(line.iter().map(|s| s.as_str()).collect())
        );
    }
    out
}
