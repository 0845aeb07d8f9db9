//! What a frontier prints and writes, from plain data: the table on stdout, `frontier.csv`,
//! `frontier.json` and the chart `frontier.png` ([`chart`]). Nothing here touches a file;
//! [`crate::publish`] does.

pub mod chart;

use std::fmt::Write as _;

use crate::report::fixed;
use crate::report::sweep::aligned;
use crate::study::frontier::{Boundary, Found, Frontier, Line};
use crate::study::sweep::{show_value, unit_of};

/// The axis's unit as written after values (`mm`, `MPa`, or empty).
pub fn unit(f: &Frontier) -> String {
    unit_of(&f.key).trim().to_string()
}

/// Decimals that show a tenth of a step of the sweep file's grid (of its first step when the
/// axis is even in the logarithm).
pub fn decimals(f: &Frontier) -> usize {
    let step = if f.log {
        f.range[0] * (f.range[1] / f.range[0]).powf(1.0 / (f.grid_values - 1) as f64) - f.range[0]
    } else {
        f.resolution()
    };
    if step.is_nan() || step <= 0.0 {
        return 2;
    }
    (1.0 - step.log10()).ceil().clamp(0.0, 6.0) as usize
}

/// The resolution asked for in words: `1 mm` or `a factor 2.37`.
pub fn resolution_words(f: &Frontier) -> String {
    if f.log {
        format!("a factor {:.3}", f.resolution())
    } else {
        format!("{} {}", v(f, f.resolution()), unit(f))
            .trim_end()
            .to_string()
    }
}

/// A value of the axis: to a tenth of the grid's step, and to three significant digits at
/// least (a range's end at 0.001 kN on a 2.5 kN step is not "0").
fn v(f: &Frontier, x: f64) -> String {
    let mut d = decimals(f);
    if x != 0.0 && x.is_finite() && x.abs() < 100.0 * 10f64.powi(-(d as i32)) {
        d = ((2.0 - x.abs().log10()).floor() as usize).clamp(d, 9);
    }
    fixed(x, d)
}

/// A boundary in words: `r ≥ 7.38 mm (shear)`.
pub fn boundary_words(f: &Frontier, b: &Boundary) -> String {
    let sign = if b.feasible_above { "≥" } else { "≤" };
    let u = unit(f);
    let space = if u.is_empty() { "" } else { " " };
    format!(
        "{} {sign} {}{space}{u} ({})",
        f.column,
        v(f, b.value),
        b.governing.name()
    )
}

/// What a line's search found, in words, with the runs that did not answer.
pub fn found_words(f: &Frontier, line: &Line) -> String {
    let mut words = answer_words(f, line);
    for (x, why) in &line.unanswered {
        let short: String = why.chars().take(80).collect();
        let u = unit(f);
        let space = if u.is_empty() { "" } else { " " };
        let at = format!("{} {}{space}{u}", f.column, v(f, *x));
        let _ = write!(words, "; no answer at {at}: {short}");
    }
    words
}

/// What a line's search found, in words.
fn answer_words(f: &Frontier, line: &Line) -> String {
    let u = unit(f);
    let space = if u.is_empty() { "" } else { " " };
    match &line.found {
        Found::Boundaries(bs) if bs.len() == 2 && bs[0].feasible_above && !bs[1].feasible_above => {
            format!(
                "feasible for {} {}–{}{space}{u} ({} below, {} above)",
                f.column,
                v(f, bs[0].value),
                v(f, bs[1].value),
                bs[0].governing.name(),
                bs[1].governing.name()
            )
        }
        Found::Boundaries(bs) => {
            let words: Vec<String> = bs.iter().map(|b| boundary_words(f, b)).collect();
            format!("feasible where {}", words.join(" and "))
        }
        Found::Whole { over, range } if over.is_empty() => format!(
            "FEASIBLE over {} {}–{}{space}{u}",
            f.column,
            v(f, range[0]),
            v(f, range[1])
        ),
        Found::Whole { over, range } => {
            let names: Vec<&str> = over.iter().map(|g| g.name()).collect();
            // Runs whose band holds the limit: the range's verdict is close there.
            let marginal: Vec<String> = (line.runs.iter())
                .filter(|p| p.verdict == crate::verdict::Verdict::Marginal)
                .map(|p| v(f, p.value))
                .collect();
            let close = if marginal.is_empty() {
                String::new()
            } else {
                format!(
                    "; MARGINAL at {} {}{space}{u}",
                    f.column,
                    marginal.join(", ")
                )
            };
            format!(
                "INFEASIBLE over {} {}–{}{space}{u} ({}){close}",
                f.column,
                v(f, range[0]),
                v(f, range[1]),
                names.join(", ")
            )
        }
        Found::NoAnswer(why) => format!("no answer: {why}"),
        Found::Stopped => "stopped before the search ended".into(),
    }
}

/// The combination's values in words: `rp 6 mm, rm 5 mm`.
pub fn combo_words(line: &Line) -> String {
    let parts: Vec<String> = (line.values.iter())
        .map(|(c, k, x)| format!("{c} {}{}", show_value(x), unit_of(k)))
        .collect();
    if parts.is_empty() {
        "the sweep's one combination".into()
    } else {
        parts.join(", ")
    }
}

/// The table printed at the end: a row per boundary (or per combination without one).
pub fn table(f: &Frontier) -> String {
    let u = unit(f);
    let mut head: Vec<(String, String)> = Vec::new();
    if let Some(line) = f.lines.first() {
        for (c, k, _) in &line.values {
            head.push((c.clone(), unit_of(k).trim().to_string()));
        }
    }
    let lead = head.len();
    for (n, unit) in [
        (f.column.as_str(), u.as_str()),
        ("from", u.as_str()),
        ("to", u.as_str()),
        ("limit", ""),
        ("feasible", ""),
        ("runs", ""),
        ("", ""),
    ] {
        head.push((n.to_string(), unit.to_string()));
    }
    let mut body = Vec::new();
    for line in &f.lines {
        let values: Vec<String> = line.values.iter().map(|(_, _, x)| show_value(x)).collect();
        for r in csv_records(f, line) {
            let mut cells = values.clone();
            cells.extend([
                r.boundary.map_or("–".into(), |x| v(f, x)),
                r.interval.map_or("–".into(), |[a, _]| v(f, a)),
                r.interval.map_or("–".into(), |[_, b]| v(f, b)),
                r.governing.clone(),
                r.feasible.clone(),
                line.runs.len().to_string(),
                r.note.clone(),
            ]);
            body.push(cells);
        }
    }
    let mut out = format!(
        "The frontier along {} ({}–{} {u}, to {}, a step of the sweep file's {} values):\n",
        f.column,
        v(f, f.range[0]),
        v(f, f.range[1]),
        resolution_words(f),
        f.grid_values
    );
    out.push_str(&aligned(&head, &body, lead.min(1)));
    let _ = writeln!(
        out,
        "from–to: the MARGINAL zone (the figure within the level's error band of its limit) and the \
         search's own tolerance"
    );
    out
}

/// One record of `frontier.csv` (and one line of the table).
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    pub boundary: Option<f64>,
    pub interval: Option<[f64; 2]>,
    pub search: Option<[f64; 2]>,
    pub governing: String,
    /// `above`, `below` (the side where this limit is met), `everywhere`, `nowhere`, or empty.
    pub feasible: String,
    pub note: String,
}

/// A line's records: one per boundary, or one saying what the whole range is.
pub fn csv_records(f: &Frontier, line: &Line) -> Vec<Record> {
    let note = found_words(f, line);
    match &line.found {
        Found::Boundaries(bs) => bs
            .iter()
            .map(|b| Record {
                boundary: Some(b.value),
                interval: Some(b.interval),
                search: Some(b.search),
                governing: b.governing.name().into(),
                feasible: if b.feasible_above { "above" } else { "below" }.into(),
                note: note.clone(),
            })
            .collect(),
        Found::Whole { over, .. } => vec![Record {
            boundary: None,
            interval: None,
            search: None,
            governing: over.iter().map(|g| g.name()).collect::<Vec<_>>().join("+"),
            feasible: if over.is_empty() {
                "everywhere"
            } else {
                "nowhere"
            }
            .into(),
            note,
        }],
        Found::NoAnswer(_) | Found::Stopped => vec![Record {
            boundary: None,
            interval: None,
            search: None,
            governing: String::new(),
            feasible: String::new(),
            note,
        }],
    }
}

/// The text of `frontier.csv`: the other axes' values, the boundary, its interval (with the
/// MARGINAL zone) and the search's, the governing limit, the side, the runs and a note.
pub fn frontier_csv(f: &Frontier) -> String {
    let u = unit(f).to_lowercase().replace('°', "deg");
    let suffix = if u.is_empty() {
        String::new()
    } else {
        format!("_{u}")
    };
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut head: Vec<String> = (f.lines.first().into_iter())
        .flat_map(|l| l.values.iter().map(|(c, _, _)| c.clone()))
        .collect();
    head.push("along".into());
    for n in ["boundary", "low", "high", "search_low", "search_high"] {
        head.push(format!("{n}{suffix}"));
    }
    head.extend(["governing", "feasible", "runs", "note"].map(String::from));
    w.write_record(&head).expect("writing to memory");
    let num = |x: Option<f64>| x.map(|x| format!("{x:.6}")).unwrap_or_default();
    for line in &f.lines {
        for r in csv_records(f, line) {
            let mut rec: Vec<String> = line.values.iter().map(|(_, _, x)| show_value(x)).collect();
            rec.push(f.column.clone());
            rec.push(num(r.boundary));
            rec.push(num(r.interval.map(|i| i[0])));
            rec.push(num(r.interval.map(|i| i[1])));
            rec.push(num(r.search.map(|i| i[0])));
            rec.push(num(r.search.map(|i| i[1])));
            rec.extend([r.governing, r.feasible, line.runs.len().to_string(), r.note]);
            w.write_record(&rec).expect("writing to memory");
        }
    }
    String::from_utf8(w.into_inner().expect("writing to memory")).expect("UTF-8")
}

/// The text of `frontier.json`: the axis, the range, the runs against the grid's, and each
/// line with its boundaries (or what its whole range is) and its runs.
pub fn frontier_json(f: &Frontier, accuracy: Option<&str>) -> String {
    let lines: Vec<serde_json::Value> = f
        .lines
        .iter()
        .map(|line| {
            let values: serde_json::Map<String, serde_json::Value> = (line.values.iter())
                .map(|(c, _, x)| (c.clone(), serde_json::to_value(x).unwrap_or_default()))
                .collect();
            let records: Vec<serde_json::Value> = csv_records(f, line)
                .into_iter()
                .filter(|r| r.boundary.is_some())
                .map(|r| {
                    serde_json::json!({
                        "value": r.boundary, "interval": r.interval, "search": r.search,
                        "governing": r.governing, "feasible": r.feasible,
                    })
                })
                .collect();
            let runs: Vec<serde_json::Value> = (line.runs.iter())
                .map(|p| serde_json::json!({"value": p.value, "design": p.design, "verdict": p.verdict}))
                .collect();
            serde_json::json!({
                "values": values,
                "boundaries": records,
                "found": found_words(f, line),
                "runs": runs,
            })
        })
        .collect();
    let obj = serde_json::json!({
        "program": "wovenform",
        "version": env!("CARGO_PKG_VERSION"),
        "along": f.column,
        "key": f.key,
        "unit": unit(f),
        "range": f.range,
        "resolution": f.resolution(),
        "grid_values": f.grid_values,
        "accuracy": accuracy,
        "runs": f.runs(),
        "grid_runs": f.grid_runs(),
        "ran_now": f.ran,
        "found_from_before": f.kept,
        "wall_s": f.wall_s,
        "lines": lines,
    });
    serde_json::to_string_pretty(&obj).expect("plain data") + "\n"
}

/// The closing line: the runs against the grid's.
pub fn runs_line(f: &Frontier) -> String {
    let (runs, grid) = (f.runs(), f.grid_runs());
    let ratio = if grid > 0 {
        runs as f64 / grid as f64
    } else {
        0.0
    };
    format!(
        "{runs} runs against {grid} for the grid of {} values along {} ({ratio:.2}×); {} run now, \
         {} found from before; {:.1} s",
        f.grid_values, f.column, f.ran, f.kept, f.wall_s
    )
}
