//! Identification of the law's transverse parameters `A`, `B` (and optionally one yarn stiffness
//! `C` for both yarns) from measured biaxial tension curves, by Levenberg–Marquardt.
//!
//! Data (`samples.rs`): fabric strains along warp and weft and the measured tensions per yarn.
//! Residuals are `model − data` on both tensions of every row. The parameters are kept in their
//! physical range by fitting `A = H·σ(x0)` (`H = e01 + e02`, σ the logistic function, so
//! `0 < A < H`), `B = exp(x1)`, `C = exp(x2)`.

use nalgebra::{DMatrix, DVector};

use crate::core::fabric::law::{CellLaw, CellParams};

mod identify;
pub mod refine;
mod samples;
pub mod shear;

pub use identify::{ParamCheck, percent};
pub use samples::{
    COLUMNS, Problem, STRAIN_RANGE, Sample, SamplesError, parse_samples, read_samples,
};

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
#[derive(Clone, Debug, PartialEq)]
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
    /// What the data say about each fitted parameter (`A`, `B`, then `C` if fitted).
    pub checks: Vec<ParamCheck>,
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

    /// What the data say about each parameter at `x` (residuals `r`).
    fn checks(&self, x: &DVector<f64>, r: &DVector<f64>) -> Vec<ParamCheck> {
        let p = self.params(x);
        let mut names = vec!["A", "B"];
        let mut values = vec![p.a, p.b];
        // d ln A / d x0 = 1 − A/H (the logistic map); ln B = x1, ln C = x2.
        let mut dlog = vec![1.0 - p.a / self.h, 1.0];
        let mut bounds = vec![identify::a_bound(p.a, self.h), None];
        if self.fit_c {
            names.push("C");
            values.push(p.c[0]);
            dlog.push(1.0);
            bounds.push(None);
        }
        let j = self.jacobian(x);
        identify::check_params(self.samples, &names, &values, &dlog, &bounds, &j, r)
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

/// Why the law cannot be fitted to the data.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FitError {
    #[error("the linear yarn law (fabric.undulation = false) has no A or B to identify")]
    LinearLaw,
    #[error(
        "{points} data points give {} residuals: at least {} are needed to identify {parameters} parameters",
        2 * points,
        parameters + 1
    )]
    TooFewPoints { points: usize, parameters: usize },
    #[error("the fit diverged (non-finite residuals)")]
    Diverged,
    #[error("{0}")]
    NoInformation(String),
}

/// Fits `A`, `B` (and `C` with `options.fit_c`) to the samples, starting from `start`.
pub fn fit(
    samples: &[Sample],
    start: CellParams,
    options: FitOptions,
) -> Result<FitResult, FitError> {
    if !start.undulation {
        return Err(FitError::LinearLaw);
    }
    let model = Model {
        start,
        h: start.e0[0] + start.e0[1],
        fit_c: options.fit_c,
        samples,
    };
    let n_par = if options.fit_c { 3 } else { 2 };
    if 2 * samples.len() <= n_par {
        return Err(FitError::TooFewPoints {
            points: samples.len(),
            parameters: n_par,
        });
    }
    if let Some(why) = identify::no_information(samples) {
        return Err(FitError::NoInformation(why));
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
        let Some((x_new, r_new, cost_new, small_step)) =
            damped_step(&model, &x, cost, (&jtj, &g, diag_max), &mut lambda)
        else {
            // No step reduces the cost any more: a minimum to machine precision.
            converged = true;
            break;
        };
        let small_gain = cost - cost_new <= 1e-12 * cost;
        x = x_new;
        r = r_new;
        cost = cost_new;
        converged = small_step || small_gain;
        iterations += 1;
    }
    let params = model.params(&x);
    let rms_n = (r.norm_squared() / r.len() as f64).sqrt();
    if !rms_n.is_finite() {
        return Err(FitError::Diverged);
    }
    let checks = model.checks(&x, &r);
    if checks
        .iter()
        .all(|c| c.unidentified() || c.at_bound.is_some())
    {
        let why: Vec<String> = checks.iter().filter_map(ParamCheck::warning).collect();
        return Err(FitError::NoInformation(format!(
            "the data carry too little information on the law: no parameter is identified ({})",
            why.join("; ")
        )));
    }
    Ok(FitResult {
        params,
        rms_n,
        points: samples.len(),
        iterations,
        converged,
        checks,
    })
}

/// One Levenberg–Marquardt step from `x` (of cost `cost`, with the normal matrix `JᵀJ`, the
/// gradient `Jᵀr` and the largest diagonal of `JᵀJ`): the damping `lambda` raised until the
/// cost falls, then eased. The new point, its residuals and cost, and whether the step was
/// tiny; `None` when no damping reduces the cost.
fn damped_step(
    model: &Model,
    x: &DVector<f64>,
    cost: f64,
    (jtj, g, diag_max): (&DMatrix<f64>, &DVector<f64>, f64),
    lambda: &mut f64,
) -> Option<(DVector<f64>, DVector<f64>, f64, bool)> {
    while *lambda < 1e16 {
        let mut a = jtj.clone();
        for k in 0..jtj.nrows() {
            a[(k, k)] += *lambda * jtj[(k, k)].max(1e-12 * diag_max);
        }
        let step = match a.clone().cholesky() {
            Some(ch) => ch.solve(&(-g)),
            None => match a.lu().solve(&(-g)) {
                Some(s) => s,
                None => {
                    *lambda *= 4.0;
                    continue;
                }
            },
        };
        let x_new = x + &step;
        let r_new = model.residuals(&x_new);
        let cost_new = 0.5 * r_new.norm_squared();
        if cost_new.is_finite() && cost_new < cost {
            *lambda = (*lambda / 3.0).max(1e-12);
            return Some((x_new, r_new, cost_new, step.amax() <= 1e-10));
        }
        *lambda *= 4.0;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

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
