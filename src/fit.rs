//! Identification of the law's transverse parameters `A`, `B` (and optionally one yarn stiffness
//! `C` for both yarns) from measured biaxial tension curves, by Levenberg–Marquardt.
//!
//! Data: a CSV with a header naming the columns `eps1,eps2,t11,t22` (any order, other columns
//! ignored): fabric strains along warp and weft, and the measured tensions per yarn (N).
//! Residuals are `model − data` on both tensions of every row. The parameters are kept in their
//! physical range by fitting `A = H·σ(x0)` (`H = e01 + e02`, σ the logistic function, so
//! `0 < A < H`), `B = exp(x1)`, `C = exp(x2)`.

use std::path::Path;

use nalgebra::{DMatrix, DVector};

use crate::core::law::{CellLaw, CellParams};
use crate::report::plot::{Colour, LineChart, Series, Style, tick_label};

/// The strains the law is used for: `[min, max]` on each of ε11, ε22.
pub const STRAIN_RANGE: [f64; 2] = [-0.05, 0.10];

/// One measured point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// `[ε11, ε22]`.
    pub eps: [f64; 2],
    /// Measured `[T11, T22]`, N per yarn.
    pub t: [f64; 2],
    /// Line in the file (1-based).
    pub line: usize,
}

const COLUMNS: [&str; 4] = ["eps1", "eps2", "t11", "t22"];

/// Reads a data CSV; errors name the file, the line and the column.
pub fn read_samples(path: &Path) -> Result<Vec<Sample>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read the data file: {e}", path.display()))?;
    parse_samples(&text, &path.display().to_string())
}

/// Parses data CSV text; `origin` names it in errors. Blank lines and `#` comments are skipped.
pub fn parse_samples(text: &str, origin: &str) -> Result<Vec<Sample>, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let expected = "expected a header line naming the columns eps1,eps2,t11,t22";
    let (header_line, header) = lines
        .next()
        .ok_or_else(|| format!("{origin}: the file is empty: {expected}"))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut index = [0usize; 4];
    for (c, col) in COLUMNS.iter().enumerate() {
        let found: Vec<usize> = (0..names.len()).filter(|&i| names[i] == *col).collect();
        index[c] = match found[..] {
            [i] => i,
            [] => {
                return Err(format!(
                    "{origin}: line {header_line}: the header `{header}` has no column {col}: {expected}"
                ));
            }
            _ => {
                return Err(format!(
                    "{origin}: line {header_line}: the header names column {col} more than once"
                ));
            }
        };
    }
    let mut samples = Vec::new();
    for (n, line) in lines {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(format!(
                "{origin}: line {n}: expected {} comma-separated fields as in the header, found {}",
                names.len(),
                fields.len()
            ));
        }
        let mut v = [0.0; 4];
        for c in 0..4 {
            let field = fields[index[c]];
            let x: f64 = field
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| {
                    format!(
                        "{origin}: line {n}, column {}: `{field}` is not a finite number",
                        COLUMNS[c]
                    )
                })?;
            if c < 2 && !(STRAIN_RANGE[0]..=STRAIN_RANGE[1]).contains(&x) {
                return Err(format!(
                    "{origin}: line {n}, column {}: {x} is outside the law's strain range [{}, {}]",
                    COLUMNS[c], STRAIN_RANGE[0], STRAIN_RANGE[1]
                ));
            }
            v[c] = x;
        }
        samples.push(Sample {
            eps: [v[0], v[1]],
            t: [v[2], v[3]],
            line: n,
        });
    }
    if samples.is_empty() {
        return Err(format!("{origin}: no data rows after the header"));
    }
    Ok(samples)
}

/// What to identify.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitOptions {
    /// Also identify `C` (one value for both yarns).
    pub fit_c: bool,
    /// Cap on Levenberg–Marquardt iterations (accepted steps).
    pub max_iterations: usize,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            fit_c: false,
            max_iterations: 200,
        }
    }
}

/// The outcome of a fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitResult {
    /// The start parameters with `a`, `b` (and `c`) replaced by the fitted values.
    pub params: CellParams,
    /// Root mean square of the residuals over both tensions of every point, N.
    pub rms_n: f64,
    /// Number of data points (rows); the residual count is twice this.
    pub points: usize,
    /// Levenberg–Marquardt iterations (accepted steps).
    pub iterations: usize,
    /// Whether a convergence test was met before the iteration cap.
    pub converged: bool,
}

/// The parameter map between the unconstrained vector `x` and the cell parameters.
struct Model<'a> {
    start: CellParams,
    h: f64,
    fit_c: bool,
    samples: &'a [Sample],
}

impl Model<'_> {
    fn params(&self, x: &DVector<f64>) -> CellParams {
        let mut p = self.start;
        p.a = self.h / (1.0 + (-x[0]).exp());
        p.b = x[1].exp();
        if self.fit_c {
            let c = x[2].exp();
            p.c = [c, c];
        }
        p
    }

    fn initial(&self) -> DVector<f64> {
        let a = self.start.a.clamp(1e-3 * self.h, 0.99 * self.h) / self.h;
        let mut x = vec![(a / (1.0 - a)).ln(), self.start.b.max(1e-12).ln()];
        if self.fit_c {
            x.push((0.5 * (self.start.c[0].ln() + self.start.c[1].ln())).max(-700.0));
        }
        DVector::from_vec(x)
    }

    fn residuals(&self, x: &DVector<f64>) -> DVector<f64> {
        let law = CellLaw::new(self.params(x));
        let mut r = DVector::zeros(2 * self.samples.len());
        for (i, s) in self.samples.iter().enumerate() {
            let t = law.evaluate(s.eps, law.initial_state()).t;
            r[2 * i] = t[0] - s.t[0];
            r[2 * i + 1] = t[1] - s.t[1];
        }
        r
    }

    /// Central finite differences in the unconstrained coordinates.
    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let m = 2 * self.samples.len();
        let mut j = DMatrix::zeros(m, x.len());
        for k in 0..x.len() {
            let step = 1e-6 * (1.0 + x[k].abs());
            let mut xp = x.clone();
            xp[k] += step;
            let mut xm = x.clone();
            xm[k] -= step;
            let col = (self.residuals(&xp) - self.residuals(&xm)) / (2.0 * step);
            j.set_column(k, &col);
        }
        j
    }
}

/// Fits `A`, `B` (and `C` with `options.fit_c`) to the samples, starting from `start`.
pub fn fit(
    samples: &[Sample],
    start: CellParams,
    options: FitOptions,
) -> Result<FitResult, String> {
    if !start.undulation {
        return Err(
            "the linear yarn law (fabric.undulation = false) has no A or B to identify".into(),
        );
    }
    let model = Model {
        start,
        h: start.e0[0] + start.e0[1],
        fit_c: options.fit_c,
        samples,
    };
    let n_par = if options.fit_c { 3 } else { 2 };
    if 2 * samples.len() <= n_par {
        return Err(format!(
            "{} data points give {} residuals: at least {} are needed to identify {n_par} parameters",
            samples.len(),
            2 * samples.len(),
            n_par + 1
        ));
    }
    let mut x = model.initial();
    let mut r = model.residuals(&x);
    let mut cost = 0.5 * r.norm_squared();
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut converged = false;
    while iterations < options.max_iterations && !converged {
        let j = model.jacobian(&x);
        let g = j.transpose() * &r;
        let jtj = j.transpose() * &j;
        let diag_max = jtj.diagonal().max().max(1e-300);
        if g.amax() <= 1e-12 * diag_max.sqrt() * r.norm().max(1e-300) {
            converged = true;
            break;
        }
        let mut accepted = false;
        while lambda < 1e16 {
            let mut a = jtj.clone();
            for k in 0..n_par {
                a[(k, k)] += lambda * jtj[(k, k)].max(1e-12 * diag_max);
            }
            let step = match a.clone().cholesky() {
                Some(ch) => ch.solve(&(-&g)),
                None => match a.lu().solve(&(-&g)) {
                    Some(s) => s,
                    None => {
                        lambda *= 4.0;
                        continue;
                    }
                },
            };
            let x_new = &x + &step;
            let r_new = model.residuals(&x_new);
            let cost_new = 0.5 * r_new.norm_squared();
            if cost_new.is_finite() && cost_new < cost {
                let small_step = step.amax() <= 1e-10;
                let small_gain = cost - cost_new <= 1e-12 * cost;
                x = x_new;
                r = r_new;
                cost = cost_new;
                lambda = (lambda / 3.0).max(1e-12);
                accepted = true;
                converged = small_step || small_gain;
                break;
            }
            lambda *= 4.0;
        }
        if !accepted {
            // No step reduces the cost any more: a minimum to machine precision.
            converged = true;
            break;
        }
        iterations += 1;
    }
    let params = model.params(&x);
    let rms_n = (r.norm_squared() / r.len() as f64).sqrt();
    if !rms_n.is_finite() {
        return Err("the fit diverged (non-finite residuals)".into());
    }
    Ok(FitResult {
        params,
        rms_n,
        points: samples.len(),
        iterations,
        converged,
    })
}

/// The strain path a sample lies on, as the angle of `(ε11, ε22)` rounded to 0.5°.
fn path_key(eps: [f64; 2]) -> Option<i64> {
    if eps[0].abs() < 1e-12 && eps[1].abs() < 1e-12 {
        return None;
    }
    Some((eps[1].atan2(eps[0]).to_degrees() * 2.0).round() as i64)
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
            let mut warp = Vec::new();
            let mut weft = Vec::new();
            let mut state = law.initial_state();
            for k in 0..=100 {
                let f = k as f64 / 100.0;
                let eps = [f * far.eps[0], f * far.eps[1]];
                let r = law.evaluate(eps, state);
                state = r.crimp;
                warp.push((pct(eps[0]), r.t[0]));
                weft.push((pct(eps[0]), r.t[1]));
            }
            let name = if far.eps[1].abs() < 1e-12 {
                "ε22 = 0".to_string()
            } else if far.eps[0].abs() < 1e-12 {
                "ε11 = 0".to_string()
            } else {
                let k = far.eps[0] / far.eps[1];
                format!("k = ε11/ε22 = {}", tick_label((k * 1e3).round() / 1e3))
            };
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_numbers_are_checked_by_line_and_column() {
        let e = parse_samples("eps1,eps2,t11\n0,0,0\n", "d.csv").unwrap_err();
        assert!(e.starts_with("d.csv: line 1:") && e.contains("t22"), "{e}");
        let e = parse_samples("eps1,eps2,t11,t22\n0.001,0,x,0\n", "d.csv").unwrap_err();
        assert!(e.starts_with("d.csv: line 2, column t11: `x`"), "{e}");
        let e = parse_samples("t22,t11,eps2,eps1\n# c\n\n1,2,0,0.5\n", "d.csv").unwrap_err();
        assert!(e.starts_with("d.csv: line 4, column eps1"), "{e}");
        let s = parse_samples("t22,t11,eps2,eps1\n1,2,0.001,0.002\n", "d.csv").unwrap();
        assert_eq!(s[0].eps, [0.002, 0.001]);
        assert_eq!(s[0].t, [2.0, 1.0]);
    }

    #[test]
    fn exact_data_are_fitted_exactly() {
        let truth = CellParams {
            a: 0.06,
            b: 0.4,
            ..CellParams::PAPER_GLASS
        };
        let law = CellLaw::new(truth);
        let samples: Vec<Sample> = (1..=40)
            .flat_map(|i| {
                let e = 0.0003 * i as f64;
                [[e, e], [e, 0.5 * e], [e, 0.0]]
            })
            .map(|eps| Sample {
                eps,
                t: law.evaluate(eps, law.initial_state()).t,
                line: 0,
            })
            .collect();
        let f = fit(&samples, CellParams::PAPER_GLASS, FitOptions::default()).unwrap();
        assert!((f.params.a / 0.06 - 1.0).abs() < 1e-6, "{f:?}");
        assert!((f.params.b / 0.4 - 1.0).abs() < 1e-6, "{f:?}");
        assert!(f.rms_n < 1e-6, "{f:?}");
        assert!(f.converged);
    }
}
