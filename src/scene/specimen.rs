//! The bias-extension specimen a user asks for on the command line (`bias`, `fit --bias`):
//! its sizes, its mesh and its options checked against physical and machine bounds before any
//! allocation, as the scene's own keys are in `validate.rs`. Errors name the option.

use crate::core::specimens::bias::BiasProblem;
use crate::core::specimens::cantilever::CantileverProblem;

use super::{Scene, SceneError};

/// The longest side of a specimen, mm (10 m).
pub const MAX_SIDE_MM: f64 = 1e4;
/// The most elements a specimen is meshed with.
pub const MAX_ELEMENTS: f64 = 2e5;
/// The fewest elements along a cantilever's overhang: the tip's deflection is then within 1 %
/// of a converged mesh's (measured on a 0.08 N·mm, 300 g/m² strip at 20 and 60 mm: +0.9 % at
/// 10 elements, +1.5 % at 8, +3.9 % at 5, +25 % at 2; the error falls as `1/n²`).
pub const MIN_CANTILEVER_ELEMENTS: f64 = 10.0;
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
        toe_strain: crate::core::specimens::bias::BIAS_TOE_STRAIN,
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

/// The heavy cantilever of `scene`'s fabric on an overhang `l` × `w` mm meshed in
/// `element_size` mm elements, every bound checked before any allocation. `origin_of` names
/// who set a scene key (a `--set`, else the scene file).
pub fn cantilever_problem(
    scene: &Scene,
    [l, w]: [f64; 2],
    element_size: f64,
    origin_of: &dyn Fn(&[&str]) -> String,
) -> Result<CantileverProblem, SceneError> {
    let (l, w) = (length_mm("length", l)?, length_mm("width", w)?);
    let h = length_mm("element-size", element_size)?;
    let along = (l / h * (1.0 - 1e-9)).ceil();
    if along < MIN_CANTILEVER_ELEMENTS {
        return Err(bad(
            &format!("--length {l} --element-size {h}"),
            format!(
                "an overhang of {l} mm in {h} mm elements has {along:.0} along it: expected \
                 at least {MIN_CANTILEVER_ELEMENTS:.0} (the tip is then within 1 % of a fine \
                 mesh's; at 2 elements it is 25 % off): an --element-size of at most {} mm",
                crate::show::Num(l / MIN_CANTILEVER_ELEMENTS)
            ),
        ));
    }
    let elements = (along + 2.0) * (w / h).round().max(1.0);
    if elements > MAX_ELEMENTS {
        return Err(bad(
            &format!("--element-size {h}"),
            format!(
                "a {l} × {w} mm strip in {h} mm elements is {elements:.0} elements: expected at \
                 most {MAX_ELEMENTS:.0} (a larger --element-size, or a narrower --width: the \
                 strip bends alike across its width)"
            ),
        ));
    }
    let key = |key: &str, detail: String| SceneError {
        origin: origin_of(&[key]),
        key: Some(key.to_string()),
        detail: format!("{key} {detail}"),
    };
    let f = &scene.fabric;
    let rigidity = f.bending_rigidity.ok_or_else(|| {
        key(
            "fabric.bending_rigidity",
            "is not set: the cantilever needs the fabric's bending rigidity [B1, B2] (N·mm)".into(),
        )
    })?;
    let mass = f.areal_mass.ok_or_else(|| {
        key(
            "fabric.areal_mass",
            "is not set: the cantilever needs the fabric's areal mass (g/m²)".into(),
        )
    })?;
    if !(rigidity[0].is_finite() && rigidity[0] > 0.0) {
        return Err(key(
            "fabric.bending_rigidity",
            format!(
                "= [{}, {}]: the cantilever bends the warp: expected its rigidity B1 > 0 N·mm",
                crate::show::Num(rigidity[0]),
                crate::show::Num(rigidity[1])
            ),
        ));
    }
    let bending = scene.bending().expect("bending rigidity is set");
    Ok(CantileverProblem {
        fabric: scene.to_cell_params(),
        bending_rigidity: rigidity,
        compression: bending.compression,
        areal_mass_g_m2: mass,
        length: l,
        width: w,
        element_size: h,
        solver: scene.to_problem().solver,
    })
}
