//! The rows of `results.csv`: one per design, what came of it; written and read with the `csv`
//! crate.

use std::collections::HashMap;

use serde::Serialize;
use serde::Serializer;
use serde::ser::SerializeMap;

use super::grid::{Column, Design};
use super::plan::Plan;
use super::values::show_value;
use crate::summary::RunSummary;
use crate::verdict::{Figures, Judged, Limits, Verdict};

/// The columns of `results.csv` after the parameters, in order: the contract's figures, then
/// the design's id, its verdict and why it failed or is invalid, then the wrinkle amplitude and
/// its error (empty for the paper's membrane), then what the run cost: its load steps and
/// Newton iterations (each group added after the rest, at the end so that every other column
/// keeps its place).
pub const FIGURE_COLUMNS: [&str; 17] = [
    "max_shear_deg",
    "max_tension_n",
    "punch_force_n",
    "max_shear_err_deg",
    "max_tension_err_pct",
    "punch_force_err_pct",
    "feasible",
    "converged",
    "wall_s",
    "map",
    "design",
    "verdict",
    "failure",
    "max_wrinkle_mm",
    "max_wrinkle_err_mm",
    "steps",
    "newton_iterations",
];

/// The columns a `results.csv` written before them may lack (read as empty).
pub const LATER_COLUMNS: [&str; 4] = [
    "max_wrinkle_mm",
    "max_wrinkle_err_mm",
    "steps",
    "newton_iterations",
];

/// One row of the results: a design and what came of it.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub design: String,
    pub index: usize,
    /// (column, value) for every parameter column.
    pub params: Vec<(String, toml::Value)>,
    /// Rounded to the precision printed in `results.csv` (°: 4 decimals; N, s: 3).
    pub max_shear_deg: Option<f64>,
    pub max_tension_n: Option<f64>,
    pub punch_force_n: Option<f64>,
    /// How far each figure can be off (°, % of the tension, % of the force): the level's.
    pub max_shear_err_deg: Option<f64>,
    pub max_tension_err_pct: Option<f64>,
    pub punch_force_err_pct: Option<f64>,
    pub feasible: bool,
    pub converged: bool,
    pub wall_s: Option<f64>,
    /// `maps/<id>.png`, for designs that ran.
    pub map: Option<String>,
    pub verdict: Verdict,
    pub failure: Option<String>,
    /// The wrinkle amplitude and its error, mm (to 3 decimals), when the scene has bending.
    pub max_wrinkle_mm: Option<f64>,
    pub max_wrinkle_err_mm: Option<f64>,
    /// The load steps and Newton iterations the run took (to where it stopped, for one that
    /// failed); `None` for a design that was not solved (invalid, or the program failed).
    pub steps: Option<u32>,
    pub newton_iterations: Option<u32>,
}

impl Serialize for Row {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        struct Params<'a>(&'a [(String, toml::Value)]);
        impl Serialize for Params<'_> {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                let mut m = s.serialize_map(Some(self.0.len()))?;
                for (k, v) in self.0 {
                    m.serialize_entry(k, v)?;
                }
                m.end()
            }
        }
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("design", &self.design)?;
        m.serialize_entry("index", &self.index)?;
        m.serialize_entry("params", &Params(&self.params))?;
        m.serialize_entry("max_shear_deg", &self.max_shear_deg)?;
        m.serialize_entry("max_tension_n", &self.max_tension_n)?;
        m.serialize_entry("punch_force_n", &self.punch_force_n)?;
        m.serialize_entry("max_shear_err_deg", &self.max_shear_err_deg)?;
        m.serialize_entry("max_tension_err_pct", &self.max_tension_err_pct)?;
        m.serialize_entry("punch_force_err_pct", &self.punch_force_err_pct)?;
        m.serialize_entry("feasible", &self.feasible)?;
        m.serialize_entry("converged", &self.converged)?;
        m.serialize_entry("wall_s", &self.wall_s)?;
        m.serialize_entry("map", &self.map)?;
        m.serialize_entry("verdict", &self.verdict)?;
        m.serialize_entry("failure", &self.failure)?;
        m.serialize_entry("max_wrinkle_mm", &self.max_wrinkle_mm)?;
        m.serialize_entry("max_wrinkle_err_mm", &self.max_wrinkle_err_mm)?;
        m.serialize_entry("steps", &self.steps)?;
        m.serialize_entry("newton_iterations", &self.newton_iterations)?;
        m.end()
    }
}

pub(super) fn round_to(v: f64, decimals: i32) -> f64 {
    let s = 10f64.powi(decimals);
    // + 0.0: a rounded -0.0 reads 0, as people write it.
    (v * s).round() / s + 0.0
}

/// One CSV record (RFC 4180 quoting where needed) with its newline; line breaks inside a field
/// become spaces, so that a record is one line.
pub(super) fn csv_line(fields: &[String]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(fields.iter().map(|f| f.replace(['\n', '\r'], " ")))
        .expect("writing to memory");
    String::from_utf8(w.into_inner().expect("writing to memory")).expect("UTF-8 in, UTF-8 out")
}

/// The names of the columns of `results.csv`: the parameters, then [`FIGURE_COLUMNS`].
pub fn column_names(columns: &[Column]) -> Vec<String> {
    let names = columns.iter().map(|c| c.name.clone());
    names.chain(FIGURE_COLUMNS.map(String::from)).collect()
}

/// The header of `results.csv` (without its newline).
pub fn csv_header(columns: &[Column]) -> String {
    csv_line(&column_names(columns)).trim_end().to_string()
}

impl Row {
    /// The row as a CSV line (with its newline).
    pub fn to_csv(&self) -> String {
        let opt = |v: Option<f64>, d: usize| {
            v.map(|v| crate::show::Fixed(v, d).to_string())
                .unwrap_or_default()
        };
        let mut fields: Vec<String> = self.params.iter().map(|(_, v)| show_value(v)).collect();
        fields.extend([
            opt(self.max_shear_deg, 4),
            opt(self.max_tension_n, 3),
            opt(self.punch_force_n, 3),
            opt(self.max_shear_err_deg, 2),
            opt(self.max_tension_err_pct, 2),
            opt(self.punch_force_err_pct, 2),
            self.feasible.to_string(),
            self.converged.to_string(),
            opt(self.wall_s, 3),
            self.map.clone().unwrap_or_default(),
            self.design.clone(),
            self.verdict.word().to_string(),
            self.failure.clone().unwrap_or_default(),
            opt(self.max_wrinkle_mm, 3),
            opt(self.max_wrinkle_err_mm, 3),
            self.steps.map(|n| n.to_string()).unwrap_or_default(),
            self.newton_iterations
                .map(|n| n.to_string())
                .unwrap_or_default(),
        ]);
        csv_line(&fields)
    }

    /// The row of `design` (its id and index) with its parameters and `verdict`, and nothing
    /// else: no figure, no error band, not converged nor feasible, no time, map, failure or
    /// counts. Every row starts here and adds what it knows.
    pub fn new(design: &Design, params: Vec<(String, toml::Value)>, verdict: Verdict) -> Row {
        Row {
            design: design.id.clone(),
            index: design.index,
            params,
            max_shear_deg: None,
            max_tension_n: None,
            punch_force_n: None,
            max_shear_err_deg: None,
            max_tension_err_pct: None,
            punch_force_err_pct: None,
            feasible: false,
            converged: false,
            wall_s: None,
            map: None,
            verdict,
            failure: None,
            max_wrinkle_mm: None,
            max_wrinkle_err_mm: None,
            steps: None,
            newton_iterations: None,
        }
    }

    pub(super) fn invalid(plan: &Plan, columns: &[Column], design: &Design, reason: String) -> Row {
        Row {
            failure: Some(reason),
            ..Row::new(design, plan.params(columns, design), Verdict::Invalid)
        }
    }

    pub(super) fn failed(
        plan: &Plan,
        columns: &[Column],
        design: &Design,
        reason: String,
        wall: f64,
    ) -> Row {
        Row {
            verdict: Verdict::Failed,
            wall_s: Some(round_to(wall, 3)),
            ..Row::invalid(plan, columns, design, reason)
        }
    }

    pub(super) fn from_summary(
        plan: &Plan,
        columns: &[Column],
        design: &Design,
        s: &RunSummary,
    ) -> Row {
        let verdict = s.judged.verdict;
        Row {
            max_shear_deg: Some(round_to(s.max_shear_deg, 4)),
            max_tension_n: Some(round_to(s.max_tension_n, 3)),
            punch_force_n: Some(round_to(s.punch_force_n, 3)),
            max_shear_err_deg: s.max_shear_err_deg,
            max_tension_err_pct: s.max_tension_err_pct,
            punch_force_err_pct: s.punch_force_err_pct,
            feasible: s.feasible,
            converged: s.converged,
            wall_s: Some(round_to(s.wall_s, 3)),
            map: Some(format!("maps/{}.png", design.id)),
            failure: s.failure.clone().or_else(|| {
                (!s.unsound.is_empty()).then(|| format!("not sound: {}", s.unsound.join("; ")))
            }),
            max_wrinkle_mm: s.max_wrinkle_mm.map(|w| round_to(w, 3)),
            max_wrinkle_err_mm: s.max_wrinkle_err_mm.map(|w| round_to(w, 3)),
            steps: Some(s.steps),
            newton_iterations: Some(s.newton_iterations),
            ..Row::new(design, plan.params(columns, design), verdict)
        }
    }

    /// The figures the row answered (an error not known counts 0), if it has both.
    pub fn figures(&self) -> Option<Figures> {
        Some(Figures {
            max_shear_deg: self.max_shear_deg?,
            max_tension_n: self.max_tension_n?,
            max_shear_err_deg: self.max_shear_err_deg.unwrap_or(0.0),
            max_tension_err_pct: self.max_tension_err_pct.unwrap_or(0.0),
            max_wrinkle_mm: self.max_wrinkle_mm,
            max_wrinkle_err_mm: self.max_wrinkle_err_mm.unwrap_or(0.0),
        })
    }

    /// The row's verdict and the limit(s) of `limits` that decide it, by its figures' bands.
    pub fn judged(&self, limits: Limits) -> Judged {
        Judged::explain(self.verdict, self.figures().as_ref(), limits)
    }

    /// The row judged again against `limits`: the figures and their errors stay, the verdict
    /// and `feasible` follow the new limits. Rows without an answer (failed, invalid, not
    /// sound) keep theirs.
    pub fn rejudge(&mut self, limits: Limits) {
        let answered = matches!(
            self.verdict,
            Verdict::Feasible | Verdict::Marginal | Verdict::Infeasible
        );
        let Some(figures) = self.figures().filter(|_| answered) else {
            return;
        };
        self.verdict = Judged::of(&figures, limits).verdict;
        self.feasible = self.verdict == Verdict::Feasible;
    }

    /// Reads a row from its CSV fields; the design must be in the grid. `None` if anything is
    /// off (a row half-written, from another grid, or with a figure that does not parse).
    pub(super) fn from_csv(
        header: &HashMap<&str, usize>,
        fields: &csv::StringRecord,
        plan: &Plan,
        columns: &[Column],
        grid: &HashMap<&str, &Design>,
    ) -> Option<Row> {
        let get = |name: &str| header.get(name).and_then(|&i| fields.get(i));
        let design = *grid.get(get("design")?)?;
        let num = |name: &str| -> Option<Option<f64>> {
            let s = get(name)?;
            if s.is_empty() {
                Some(None)
            } else {
                s.parse::<f64>().ok().filter(|v| v.is_finite()).map(Some)
            }
        };
        let boolean = |name: &str| match get(name)? {
            "true" => Some(true),
            "false" => Some(false),
            _ => None,
        };
        let text = |name: &str| get(name).filter(|s| !s.is_empty()).map(String::from);
        // A count the row lacks or that does not parse is not known: it decides nothing.
        let count = |name: &str| get(name).and_then(|s| s.parse::<u32>().ok());
        let verdict = Verdict::parse(get("verdict")?)?;
        let row = Row {
            max_shear_deg: num("max_shear_deg")?,
            max_tension_n: num("max_tension_n")?,
            punch_force_n: num("punch_force_n")?,
            max_shear_err_deg: num("max_shear_err_deg").unwrap_or(None),
            max_tension_err_pct: num("max_tension_err_pct").unwrap_or(None),
            punch_force_err_pct: num("punch_force_err_pct").unwrap_or(None),
            feasible: boolean("feasible")?,
            converged: boolean("converged")?,
            wall_s: num("wall_s")?,
            map: text("map"),
            failure: text("failure"),
            max_wrinkle_mm: num("max_wrinkle_mm").unwrap_or(None),
            max_wrinkle_err_mm: num("max_wrinkle_err_mm").unwrap_or(None),
            steps: count("steps"),
            newton_iterations: count("newton_iterations"),
            ..Row::new(design, plan.params(columns, design), verdict)
        };
        // The parameters written must be the design's (the id's hash says so too).
        for (name, v) in &row.params {
            if let Some(s) = get(name)
                && *s != show_value(v)
            {
                return None;
            }
        }
        Some(row)
    }
}

/// Counts of the verdicts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counts {
    pub feasible: usize,
    pub marginal: usize,
    pub infeasible: usize,
    pub failed: usize,
    pub invalid: usize,
}

pub fn counts<'a>(rows: impl IntoIterator<Item = &'a Row>) -> Counts {
    let mut c = Counts::default();
    for r in rows {
        match r.verdict {
            Verdict::Feasible => c.feasible += 1,
            Verdict::Marginal => c.marginal += 1,
            Verdict::Infeasible => c.infeasible += 1,
            Verdict::Failed => c.failed += 1,
            Verdict::Invalid => c.invalid += 1,
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::super::plan::tests::plan_of;
    use super::*;

    #[test]
    fn csv_rows_round_trip() {
        let p = plan_of("[sweep]\nr = [5.0, 7.5]\n").unwrap();
        let cols = p.columns();
        let d = p.designs();
        let mut row = Row::invalid(&p, &cols, &d[1], "a, \"quoted\"\nreason".into());
        row.max_shear_deg = Some(12.3456);
        row.steps = Some(20);
        row.newton_iterations = Some(195);
        let line = row.to_csv();
        assert_eq!(line.matches('\n').count(), 1, "one line per row: {line}");
        let fields = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(line.as_bytes())
            .records()
            .next()
            .unwrap()
            .unwrap();
        let names = column_names(&cols);
        assert_eq!(fields.len(), names.len());
        assert_eq!(csv_header(&cols), names.join(","));
        let header: HashMap<&str, usize> = names
            .iter()
            .enumerate()
            .map(|(i, h)| (h.as_str(), i))
            .collect();
        let grid: HashMap<&str, &Design> = d.iter().map(|d| (d.id.as_str(), d)).collect();
        let back = Row::from_csv(&header, &fields, &p, &cols, &grid).unwrap();
        row.failure = Some("a, \"quoted\" reason".into());
        assert_eq!(back, row);
    }
}
