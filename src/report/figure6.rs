//! The paper's Figure 6: warp and weft tension against warp strain for biaxial strain paths
//! of ratio `k = ε11/ε22` = 1, 2, 4 and the uniaxial path (ε22 = 0).

use crate::core::fabric::law::{CellLaw, CellParams};
use crate::report::plot::{Colour, LineChart, Series};

/// The largest warp strain drawn (the paper's figure reaches about 1 %).
pub const EPS_MAX: f64 = 0.012;

/// A straight strain path from the unstrained state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StrainPath {
    /// `ε22 = ε11 / k`.
    Ratio(f64),
    /// `ε22 = 0` (k = ∞).
    Uniaxial,
}

impl StrainPath {
    /// The figure's four paths: k = 1, 2, 4 and uniaxial.
    pub const FIGURE6: [StrainPath; 4] = [
        StrainPath::Ratio(1.0),
        StrainPath::Ratio(2.0),
        StrainPath::Ratio(4.0),
        StrainPath::Uniaxial,
    ];

    /// The weft strain on this path at warp strain `eps1`.
    pub fn weft_strain(self, eps1: f64) -> f64 {
        match self {
            StrainPath::Ratio(k) => eps1 / k,
            StrainPath::Uniaxial => 0.0,
        }
    }

    /// `k` as written in the CSV: a number, or `inf` for the uniaxial path.
    pub fn k_label(self) -> String {
        match self {
            StrainPath::Ratio(k) => format!("{k}"),
            StrainPath::Uniaxial => "inf".to_string(),
        }
    }

    /// The legend's name for the path.
    pub fn legend(self) -> String {
        match self {
            StrainPath::Ratio(k) => format!("ε11 = {k} ε22"),
            StrainPath::Uniaxial => "uniaxial (ε22 = 0)".to_string(),
        }
    }
}

/// One point of one curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Figure6Row {
    pub path: StrainPath,
    /// `[ε11, ε22]`.
    pub eps: [f64; 2],
    /// `[T11, T22]`, N per yarn.
    pub t: [f64; 2],
}

/// The curves: for each path, `points_per_curve` warp strains evenly from 0 to [`EPS_MAX`].
pub fn figure6_table(params: CellParams, points_per_curve: usize) -> Vec<Figure6Row> {
    let law = CellLaw::new(params);
    let n = points_per_curve.max(2);
    let mut rows = Vec::with_capacity(4 * n);
    for path in StrainPath::FIGURE6 {
        let mut state = law.initial_state();
        for i in 0..n {
            let eps1 = EPS_MAX * i as f64 / (n - 1) as f64;
            let eps = [eps1, path.weft_strain(eps1)];
            let r = law.evaluate(eps, state);
            state = r.crimp;
            rows.push(Figure6Row { path, eps, t: r.t });
        }
    }
    rows
}

/// The table as CSV with columns `k,eps1,eps2,t11_n,t22_n`.
pub fn figure6_csv(rows: &[Figure6Row]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let header = std::iter::once("k").chain(crate::study::fit::COLUMNS);
    w.write_record(header).expect("writing to memory");
    for r in rows {
        w.write_record([
            r.path.k_label().to_string(),
            r.eps[0].to_string(),
            r.eps[1].to_string(),
            r.t[0].to_string(),
            r.t[1].to_string(),
        ])
        .expect("writing to memory");
    }
    String::from_utf8(w.into_inner().expect("writing to memory")).expect("UTF-8")
}

/// The chart: warp tension solid, weft tension dashed, one colour per path.
pub fn figure6_chart(rows: &[Figure6Row]) -> LineChart {
    let mut chart = LineChart::new(
        "Biaxial tension of the woven cell (paper's Figure 6; k = ε11/ε22)",
        "warp strain ε11 (%)",
        "tension per yarn (N)",
    );
    for (i, path) in StrainPath::FIGURE6.into_iter().enumerate() {
        // One point in five (and the last): long straight segments draw smooth lines, where
        // a point every few pixels draws a staircase (the bitmap has no anti-aliasing).
        let all: Vec<&Figure6Row> = rows.iter().filter(|r| r.path == path).collect();
        let on_path = all
            .iter()
            .enumerate()
            .filter(|(i, _)| i % 5 == 0 || *i + 1 == all.len())
            .map(|(_, r)| *r);
        let warp = on_path
            .clone()
            .map(|r| (100.0 * r.eps[0], r.t[0]))
            .collect();
        let weft = on_path.map(|r| (100.0 * r.eps[0], r.t[1])).collect();
        let colour = Colour::nth(i);
        chart.push(Series::line(
            format!("{}: warp T11", path.legend()),
            warp,
            colour,
        ));
        chart.push(Series::dashed(
            format!("{}: weft T22", path.legend()),
            weft,
            colour,
        ));
    }
    chart
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chart_defines_k_and_draws_long_segments_through_the_ends() {
        let rows = figure6_table(CellParams::PAPER_GLASS, 121);
        let chart = figure6_chart(&rows);
        assert!(chart.title.contains("k = ε11/ε22"), "{}", chart.title);
        assert_eq!(chart.series.len(), 8);
        for s in &chart.series {
            // 121 points a curve in the CSV, 25 on the chart: one in five and the last.
            assert_eq!(s.points.len(), 25, "{}", s.name);
            assert!((s.points.last().unwrap().0 - 100.0 * EPS_MAX).abs() < 1e-9);
            assert!(s.name.contains("ε22"), "{}", s.name);
        }
    }
}
