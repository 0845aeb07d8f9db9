//! The bias-extension specimen a user asks for on the command line (`bias`, `fit --bias`):
//! its sizes, its mesh and its options checked against physical and machine bounds before any
//! allocation, as the scene's own keys are in `validate.rs`. Errors name the option.

use crate::core::bias::BiasProblem;

use super::{Scene, SceneError};

/// The longest side of a specimen, mm (10 m).
pub const MAX_SIDE_MM: f64 = 1e4;
/// The most elements a specimen is meshed with.
pub const MAX_ELEMENTS: f64 = 2e5;
/// The most refining passes of `fit --bias` (each is a whole finite-element test; two are
/// enough on the measured curves we have, see the shear-law guide).
pub const MAX_REFINE: usize = 10;

fn bad(option: &str, detail: String) -> SceneError {
    SceneError {
        origin: option.to_string(),
        key: None,
        detail,
    }
}

/// A length given as `--{option}`: finite, > 0 and at most [`MAX_SIDE_MM`].
pub fn length_mm(option: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v > 0.0 && v <= MAX_SIDE_MM {
        Ok(v)
    } else {
        Err(bad(
            &format!("--{option} {v}"),
            "expected a length in mm, > 0 and at most 10 m (10000 mm)".into(),
        ))
    }
}

/// Checks an `h × w` mm specimen pulled by `d` mm, meshed in `element_size` mm elements and
/// solved in `points` increments, against the bounds (before any allocation).
pub fn check_sizes(
    [h, w, d]: [f64; 3],
    element_size: f64,
    points: usize,
) -> Result<(), SceneError> {
    let (h, w, _) = (
        length_mm("length", h)?,
        length_mm("width", w)?,
        length_mm("stroke", d)?,
    );
    let element_size = length_mm("element-size", element_size)?;
    if !(2..=1000).contains(&points) {
        return Err(bad(
            &format!("--points {points}"),
            "expected 2 to 1000".into(),
        ));
    }
    if w < 2.0 * element_size {
        return Err(bad(
            &format!("--width {w}"),
            format!(
                "a specimen {w} mm wide is less than two {element_size} mm elements across: \
                 expected a width of at least {} mm (or a smaller --element-size; are its sizes \
                 in mm?)",
                2.0 * element_size
            ),
        ));
    }
    let elements = (h / element_size).ceil() * (w / element_size).ceil();
    if elements > MAX_ELEMENTS {
        return Err(bad(
            &format!("--element-size {element_size}"),
            format!(
                "a {h} × {w} mm specimen in {element_size} mm elements is {elements:.0} \
                 elements: expected at most {MAX_ELEMENTS:.0} (a larger --element-size, or a \
                 smaller specimen: are its sizes in mm?)"
            ),
        ));
    }
    if h <= 1.5 * w {
        return Err(bad(
            &format!("--length {h} --width {w}"),
            "a bias specimen needs a length more than 1.5 times the width (usually twice), so \
             that it has a central zone"
                .into(),
        ));
    }
    Ok(())
}

/// The bias-extension test of `scene`'s fabric on an `h × w` mm specimen pulled by `d` mm,
/// meshed in `element_size` mm elements and solved in `points` increments, every bound checked.
pub fn bias_problem(
    scene: &Scene,
    [h, w, d]: [f64; 3],
    element_size: f64,
    points: usize,
) -> Result<BiasProblem, SceneError> {
    check_sizes([h, w, d], element_size, points)?;
    let p = scene.to_problem();
    let problem = BiasProblem {
        fabric: p.fabric,
        shear: p.shear,
        length: h,
        width: w,
        stroke: d,
        element_size,
        points,
        solver: p.solver,
        toe_strain: crate::core::bias::BIAS_TOE_STRAIN,
    };
    problem.check().map_err(|e| {
        bad(
            &format!("--length {h} --width {w} --stroke {d}"),
            e.to_string(),
        )
    })?;
    Ok(problem)
}

/// The options of `fit --bias` besides the specimen: the fitted range of ideal central shear
/// (degrees), the first displacement fitted (mm) and the refining passes.
pub fn check_fit_options(
    max_shear_deg: f64,
    from_mm: f64,
    refine: usize,
) -> Result<(), SceneError> {
    if !(max_shear_deg.is_finite() && max_shear_deg > 0.0 && max_shear_deg < 90.0) {
        return Err(bad(
            &format!("--max-shear {max_shear_deg}"),
            "expected an angle in degrees, > 0 and < 90".into(),
        ));
    }
    if !(from_mm.is_finite() && (0.0..=MAX_SIDE_MM).contains(&from_mm)) {
        return Err(bad(
            &format!("--from {from_mm}"),
            "expected a grip displacement in mm, ≥ 0 and at most 10 m".into(),
        ));
    }
    if refine > MAX_REFINE {
        return Err(bad(
            &format!("--refine {refine}"),
            format!(
                "expected at most {MAX_REFINE} refining passes (each is a whole finite-element test)"
            ),
        ));
    }
    Ok(())
}
