//! What the data say about each fitted parameter: whether they carry information at all (not
//! every tension zero, more than one strain), and after the fit, for each parameter, its
//! relative uncertainty (from the Jacobian at the solution: `s² (JᵀJ)⁻¹`), how much a 10 %
//! change of it moves the model's tensions, and whether it sits on a bound of its range.

use nalgebra::{DMatrix, DVector};

use super::Sample;

/// A parameter whose 10 % change moves the tensions by less than this share of the measured
/// tensions' RMS (or of 1 mN, if larger) hardly moves the residual: the data do not see it.
const INSENSITIVE: f64 = 1e-3;
/// A parameter whose relative uncertainty (one standard deviation) is over 100 % is not pinned.
const UNCERTAIN: f64 = 1.0;
/// `A/H` within this of 0 or 1: `A` sits on a bound of its range `0 < A < e01 + e02`.
const AT_BOUND: f64 = 1e-3;

/// What the data say about one fitted parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamCheck {
    /// `A`, `B` or `C`.
    pub name: &'static str,
    pub value: f64,
    /// One standard deviation over the value (∞ when the data cannot tell it at all).
    pub rel_uncertainty: f64,
    /// RMS change of the model's tensions for a 10 % change of the parameter, N.
    pub change_n: f64,
    /// The bound it sits on, in words (`A → e01 + e02 = 0.476 mm`).
    pub at_bound: Option<String>,
    /// A change of it hardly moves the residual.
    pub insensitive: bool,
}

impl ParamCheck {
    /// Not pinned by the data: insensitive, or uncertain by more than 100 %.
    pub fn unidentified(&self) -> bool {
        self.insensitive || self.uncertain()
    }

    /// Uncertain by more than 100 % (or not at all known).
    fn uncertain(&self) -> bool {
        self.rel_uncertainty.is_nan() || self.rel_uncertainty > UNCERTAIN
    }

    /// What is wrong with the parameter, in a sentence; `None` when the data pin it.
    pub fn warning(&self) -> Option<String> {
        let mut why = Vec::new();
        if let Some(b) = &self.at_bound {
            why.push(format!("it sits on its bound ({b})"));
        }
        if self.insensitive {
            why.push(format!(
                "a 10 % change of it moves the tensions by {:.2e} N only",
                self.change_n
            ));
        } else if self.uncertain() {
            why.push(format!(
                "its uncertainty is {} of its value",
                percent(self.rel_uncertainty)
            ));
        }
        (!why.is_empty()).then(|| {
            format!(
                "{} = {:.6e} is not identified by these data: {}",
                self.name,
                self.value,
                why.join("; ")
            )
        })
    }
}

/// A relative figure as a percentage (`12 %`, `3.4e5 %`, `∞ %`).
pub fn percent(rel: f64) -> String {
    let p = 100.0 * rel;
    if !p.is_finite() {
        "∞ %".into()
    } else if p >= 1e4 {
        format!("{p:.1e} %")
    } else {
        format!("{p:.1} %")
    }
}

/// Why the data carry no information on the law's parameters, before any fit.
pub fn no_information(samples: &[Sample]) -> Option<String> {
    if samples.iter().all(|s| s.t == [0.0, 0.0]) {
        return Some(format!(
            "every measured tension of the {} points is 0: the data carry no information on A and B",
            samples.len()
        ));
    }
    let first = samples.first()?.eps;
    if samples.len() > 1 && samples.iter().all(|s| s.eps == first) {
        return Some(format!(
            "all {} points are at one strain (eps1 = {}, eps2 = {}): a curve needs at least two",
            samples.len(),
            first[0],
            first[1]
        ));
    }
    None
}

/// The checks of the fitted parameters. `j`: the Jacobian of the residuals in the fit's
/// unconstrained coordinates `x`; `r`: the residuals; `dlog`: `d ln p / d x` for each
/// parameter; `bounds`: the bound each sits on, if any.
pub fn check_params(
    samples: &[Sample],
    names: &[&'static str],
    values: &[f64],
    dlog: &[f64],
    bounds: &[Option<String>],
    j: &DMatrix<f64>,
    r: &DVector<f64>,
) -> Vec<ParamCheck> {
    let (m, n) = j.shape();
    let data_rms = (samples
        .iter()
        .map(|s| s.t[0] * s.t[0] + s.t[1] * s.t[1])
        .sum::<f64>()
        / m as f64)
        .sqrt();
    let floor = INSENSITIVE * data_rms.max(1.0);
    // d r / d ln p = J_k / (d ln p / d x): the RMS change for a 10 % change of p.
    let change_n: Vec<f64> = (0..n)
        .map(|k| 0.1 * j.column(k).norm() / dlog[k].abs().max(1e-300) / (m as f64).sqrt())
        .collect();
    let insensitive: Vec<bool> = change_n.iter().map(|c| c.is_nan() || *c < floor).collect();
    // The covariance of the parameters the residual sees (the others would make JᵀJ singular).
    let seen: Vec<usize> = (0..n).filter(|&k| !insensitive[k]).collect();
    let s2 = r.norm_squared() / (m.saturating_sub(seen.len())).max(1) as f64;
    let js = j.select_columns(&seen);
    let cov = (js.transpose() * &js).try_inverse();
    (0..n)
        .map(|k| {
            let at = seen.iter().position(|&i| i == k);
            let sigma_x = match (&cov, at) {
                (Some(c), Some(i)) => (s2 * c[(i, i)].max(0.0)).sqrt(),
                _ => f64::INFINITY,
            };
            let rel = sigma_x * dlog[k].abs();
            ParamCheck {
                name: names[k],
                value: values[k],
                rel_uncertainty: if rel.is_nan() { f64::INFINITY } else { rel },
                change_n: change_n[k],
                at_bound: bounds[k].clone(),
                insensitive: insensitive[k],
            }
        })
        .collect()
}

/// The bound `A` sits on, if it does: `a` in `(0, h)`.
pub fn a_bound(a: f64, h: f64) -> Option<String> {
    if a / h > 1.0 - AT_BOUND {
        Some(format!("A → e01 + e02 = {h} mm, its upper bound"))
    } else if a / h < AT_BOUND {
        Some("A → 0 mm, its lower bound".into())
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(eps: [f64; 2], t: [f64; 2]) -> Sample {
        Sample { eps, t, line: 2 }
    }

    #[test]
    fn data_without_information_are_named() {
        let zero = [
            sample([0.001, 0.0], [0.0; 2]),
            sample([0.002, 0.0], [0.0; 2]),
        ];
        assert!(
            no_information(&zero)
                .unwrap()
                .contains("every measured tension")
        );
        let one = [
            sample([0.001, 0.0], [1.0; 2]),
            sample([0.001, 0.0], [2.0; 2]),
        ];
        assert!(no_information(&one).unwrap().contains("one strain"));
        let fine = [
            sample([0.001, 0.0], [1.0; 2]),
            sample([0.002, 0.0], [2.0; 2]),
        ];
        assert_eq!(no_information(&fine), None);
    }

    #[test]
    fn a_parameter_the_residual_does_not_see_is_not_identified() {
        let s = [
            sample([0.001, 0.0], [10.0; 2]),
            sample([0.002, 0.0], [20.0; 2]),
        ];
        // Four residuals; the first parameter moves them, the second does not.
        let j = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 2.0, 1e-9, 3.0, 0.0, 4.0, 0.0]);
        let r = DVector::from_vec(vec![0.1, -0.1, 0.05, 0.0]);
        let c = check_params(
            &s,
            &["A", "B"],
            &[0.1, 1e98],
            &[1.0, 1.0],
            &[None, None],
            &j,
            &r,
        );
        assert!(!c[0].unidentified() && c[0].warning().is_none(), "{c:?}");
        assert!(c[1].insensitive && c[1].unidentified(), "{c:?}");
        assert!(
            c[1].warning()
                .unwrap()
                .starts_with("B = 1.000000e98 is not identified")
        );
        assert!(a_bound(0.4759, 0.476).is_some() && a_bound(0.2, 0.476).is_none());
    }
}
