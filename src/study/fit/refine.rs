//! The shear law `[k1, k3, k5]` fitted to a measured bias-extension curve and refined on the
//! finite-element test (`wovenform fit DATA.csv --bias HxW`): first on the ideal kinematics of
//! the test ([`fit_shear_law`]), then, pass after pass, with the measured force divided by the
//! finite-element test's force over the ideal one along the curve, so that the law fits the
//! data through the model that will use it.

use crate::core::specimens::bias::{BiasProblem, BiasResult, ideal_force, kinematic_limit};
use crate::scene::Scene;

use super::shear::{BiasPoint, BiasSpecimen, ShearFit, fit_points, fit_shear_law};

/// Increments of the finite-element test.
pub const FE_POINTS: usize = 30;

/// Why a shear law cannot be fitted; `data` names the measured curve.
#[derive(Debug, thiserror::Error)]
pub enum RefineError {
    #[error(
        "{data}: {used} points with a positive force from {from_mm} mm (--from) and under {max_shear_deg}° of ideal central shear (--max-shear; d < {limit:.1} mm on a {length} × {width} mm specimen): expected at least 4"
    )]
    TooFewPoints {
        data: String,
        used: usize,
        from_mm: f64,
        max_shear_deg: f64,
        limit: f64,
        length: f64,
        width: f64,
    },
    #[error("{data}: the data carry no information on the shear law (every fit is singular)")]
    NoInformation { data: String },
    /// The finite-element test cannot be set up.
    #[error("{0}")]
    Test(String),
}

/// The points of a measured curve that the fit uses (at least 4).
pub fn usable_points(
    s: &BiasSpecimen,
    points: &[BiasPoint],
    data: &str,
) -> Result<Vec<BiasPoint>, RefineError> {
    let used = fit_points(s, points);
    if used.len() < 4 {
        return Err(RefineError::TooFewPoints {
            data: data.to_string(),
            used: used.len(),
            from_mm: s.from_mm,
            max_shear_deg: s.max_shear_deg,
            limit: kinematic_limit(s.length, s.width),
            length: s.length,
            width: s.width,
        });
    }
    Ok(used)
}

/// A refined fit: the ideal kinematics' fit, the last one, and the finite-element test with
/// the last law (`problem.shear`).
pub struct Refined {
    pub ideal: ShearFit,
    pub fit: ShearFit,
    pub problem: BiasProblem,
    pub result: BiasResult,
    /// RMS of the finite-element test's force against the data, relative, over `model_points`
    /// (the points within the test's reach).
    pub model_rms_rel: f64,
    pub model_points: usize,
}

/// Fits the law to `used` (from [`usable_points`]) for `scene`'s fabric, refined by `passes`
/// finite-element tests of `element_size` mm; `on_pass(i)` hears each pass start.
pub fn refine(
    scene: &Scene,
    s: &BiasSpecimen,
    used: &[BiasPoint],
    passes: usize,
    element_size: f64,
    data: &str,
    on_pass: &mut dyn FnMut(usize),
) -> Result<Refined, RefineError> {
    let no_fit = || RefineError::NoInformation {
        data: data.to_string(),
    };
    let ideal = fit_shear_law(s, used, &|_| 1.0).ok_or_else(no_fit)?;
    let mut problem = BiasProblem {
        fabric: scene.to_cell_params(),
        shear: None,
        length: s.length,
        width: s.width,
        stroke: used.last().map_or(1.0, |p| p.displacement_mm),
        element_size,
        points: FE_POINTS,
        solver: scene.to_problem().solver,
        toe_strain: crate::core::specimens::bias::BIAS_TOE_STRAIN,
    };
    let mut fit = ideal.clone();
    let mut pass = 0;
    let result = loop {
        problem.shear = Some(fit.law);
        on_pass(pass);
        let result = (problem.solve(&mut |_| {})).map_err(|e| RefineError::Test(e.to_string()))?;
        if result.failure.is_some() || pass == passes {
            break result;
        }
        let ratio = fe_over_ideal(&problem, &result);
        fit = fit_shear_law(s, used, &|d| ratio(d)).ok_or_else(no_fit)?;
        pass += 1;
    };
    problem.shear = Some(fit.law);
    let (model_rms_rel, model_points) = model_rms(&result, used);
    Ok(Refined {
        ideal,
        fit,
        problem,
        result,
        model_rms_rel,
        model_points,
    })
}

/// The ratio of the finite-element force to the ideal force along the test, interpolated.
fn fe_over_ideal(problem: &BiasProblem, r: &BiasResult) -> impl Fn(f64) -> f64 + use<> {
    let law = problem.shear.expect("a law");
    let (h, w) = (problem.length, problem.width);
    let pairs: Vec<(f64, f64)> = r
        .displacement_mm
        .iter()
        .zip(&r.force_n)
        .filter(|(d, _)| **d > 0.0)
        .map(|(&d, &f)| {
            let ideal = ideal_force(&law, h, w, d);
            (d, if ideal > 0.0 { f / ideal } else { 1.0 })
        })
        .collect();
    move |d: f64| interpolate(&pairs, d).unwrap_or(1.0)
}

/// The RMS of the test's force against the data, relative, and the points it is taken over
/// (those within the test's reach).
fn model_rms(r: &BiasResult, used: &[BiasPoint]) -> (f64, usize) {
    let curve: Vec<(f64, f64)> = r
        .displacement_mm
        .iter()
        .copied()
        .zip(r.force_n.iter().copied())
        .collect();
    let fe = |d: f64| interpolate(&curve, d).unwrap_or(0.0);
    let reach = r.displacement_mm.last().copied().unwrap_or(0.0);
    let rel: Vec<f64> = used
        .iter()
        .filter(|p| p.displacement_mm <= reach)
        .map(|p| (fe(p.displacement_mm) - p.force_n) / p.force_n)
        .collect();
    let rms = (rel.iter().map(|v| v * v).sum::<f64>() / rel.len().max(1) as f64).sqrt();
    (rms, rel.len())
}

/// The piecewise-linear curve through `points` (increasing x) at `x`, held at its ends;
/// `None` for no points.
fn interpolate(points: &[(f64, f64)], x: f64) -> Option<f64> {
    let i = points.partition_point(|p| p.0 < x);
    match (i.checked_sub(1).and_then(|j| points.get(j)), points.get(i)) {
        (Some(a), Some(b)) if b.0 > a.0 => Some(a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)),
        (Some(a), _) => Some(a.1),
        (None, b) => b.map(|b| b.1),
    }
}

/// `scene` with the fitted law as a stand-alone `[fabric]` table (every key), headed by a
/// comment naming where the fabric and the data came from. The coefficients carry six
/// significant figures: far below the fit's own uncertainty.
pub fn fitted_fabric_toml(scene: &Scene, fit: &ShearFit, header: &str) -> String {
    let mut fitted = scene.fabric.clone();
    fitted.shear_moment = Some(fit.law.k.map(|v| format!("{v:.5e}").parse().unwrap_or(v)));
    let mut doc = toml::Table::new();
    let fabric = toml::Table::try_from(&fitted).unwrap_or_default();
    doc.insert("fabric".into(), toml::Value::Table(fabric));
    format!("{header}\n{}", toml::to_string(&doc).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::interpolate;

    #[test]
    fn interpolation_is_linear_between_points_and_held_at_the_ends() {
        let pts = [(0.0, 1.0), (2.0, 3.0), (4.0, 3.0)];
        assert_eq!(interpolate(&pts, 1.0), Some(2.0));
        assert_eq!(interpolate(&pts, -5.0), Some(1.0));
        assert_eq!(interpolate(&pts, 9.0), Some(3.0));
        assert_eq!(interpolate(&[], 1.0), None);
    }
}
