//! The fit's chart: measured tensions against the fitted law.

use crate::core::fabric::law::CellLaw;
use crate::report::plot::{Colour, LineChart, Series, Style, tick_label};
use crate::study::fit::{FitResult, Sample};

/// The strain path a sample lies on, as the angle of `(ε11, ε22)` rounded to 0.5°.
fn path_key(eps: [f64; 2]) -> Option<i64> {
    if eps[0].abs() < 1e-12 && eps[1].abs() < 1e-12 {
        return None;
    }
    Some((eps[1].atan2(eps[0]).to_degrees() * 2.0).round() as i64)
}

/// Points of a curve, (x, y).
type Curve = Vec<(f64, f64)>;

/// The model's warp and weft tensions along the straight strain path to `eps_far`, against
/// the warp strain (%), and the path's name.
fn path_curves(law: &CellLaw, eps_far: [f64; 2]) -> (String, Curve, Curve) {
    let mut warp = Vec::new();
    let mut weft = Vec::new();
    let mut state = law.initial_state();
    for k in 0..=100 {
        let f = k as f64 / 100.0;
        let eps = [f * eps_far[0], f * eps_far[1]];
        let r = law.evaluate(eps, state);
        state = r.crimp;
        warp.push((100.0 * eps[0], r.t[0]));
        weft.push((100.0 * eps[0], r.t[1]));
    }
    let name = if eps_far[1].abs() < 1e-12 {
        "ε22 = 0".to_string()
    } else if eps_far[0].abs() < 1e-12 {
        "ε11 = 0".to_string()
    } else {
        let k = eps_far[0] / eps_far[1];
        format!("k = ε11/ε22 = {}", tick_label((k * 1e3).round() / 1e3))
    };
    (name, warp, weft)
}

/// Data (markers: ● warp, × weft) against the fitted model (lines: solid warp, dashed weft),
/// tension against warp strain. Data on up to 6 straight strain paths get one model curve each;
/// otherwise the model is drawn at the data points.
pub fn fit_chart(samples: &[Sample], fit: &FitResult, title: &str) -> LineChart {
    let p = fit.params;
    let law = CellLaw::new(p);
    let mut chart = LineChart::new(title, "warp strain ε11 (%)", "tension per yarn (N)");
    let mut keys: Vec<i64> = samples.iter().filter_map(|s| path_key(s.eps)).collect();
    // Steepest weft path first: k = 1, 2, 4, …, then ε22 = 0 (as in Figure 6).
    keys.sort_unstable_by(|a, b| b.cmp(a));
    keys.dedup();
    let pct = |e: f64| 100.0 * e;
    if keys.len() <= 6 {
        for (i, key) in keys.iter().enumerate() {
            let colour = Colour::nth(i);
            let group: Vec<&Sample> = samples
                .iter()
                .filter(|s| path_key(s.eps) == Some(*key))
                .collect();
            let far = group
                .iter()
                .max_by(|a, b| {
                    a.eps[0]
                        .hypot(a.eps[1])
                        .total_cmp(&b.eps[0].hypot(b.eps[1]))
                })
                .expect("a group has a sample");
            let (name, warp, weft) = path_curves(&law, far.eps);
            chart.push(Series::line(name, warp, colour));
            chart.push(Series::dashed("", weft, colour));
            let data = |a: usize| group.iter().map(|s| (pct(s.eps[0]), s.t[a])).collect();
            chart.push(Series::markers("", data(0), colour));
            chart.push(Series::crosses("", data(1), colour));
        }
        let origin: Vec<&Sample> = samples
            .iter()
            .filter(|s| path_key(s.eps).is_none())
            .collect();
        if !origin.is_empty() {
            let data = |a: usize| origin.iter().map(|s| (0.0, s.t[a])).collect();
            chart.push(Series::markers("", data(0), Colour::GREY));
            chart.push(Series::crosses("", data(1), Colour::GREY));
        }
        for (name, style) in [
            ("warp T11: model", Style::Line),
            ("weft T22: model", Style::Dashed),
            ("warp T11: data", Style::Markers),
            ("weft T22: data", Style::Crosses),
        ] {
            chart.push(Series::new(name, vec![], style, Colour::GREY));
        }
    } else {
        let mut model = [Vec::new(), Vec::new()];
        for s in samples {
            let t = law.evaluate(s.eps, law.initial_state()).t;
            for a in 0..2 {
                model[a].push((pct(s.eps[0]), t[a]));
            }
        }
        let data = |a: usize| samples.iter().map(|s| (pct(s.eps[0]), s.t[a])).collect();
        chart.push(Series::markers("warp T11: data", data(0), Colour::GREY));
        chart.push(Series::crosses("weft T22: data", data(1), Colour::GREY));
        let [warp, weft] = model;
        chart.push(Series::markers("warp T11: model", warp, Colour::nth(0)));
        chart.push(Series::crosses("weft T22: model", weft, Colour::nth(1)));
    }
    chart
}
