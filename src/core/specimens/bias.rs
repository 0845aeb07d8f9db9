//! The bias-extension test as a scene: a rectangular specimen, `length × width` (mm) between
//! the grips, its yarns at ±45° to its length, one end clamped and the other pulled along the
//! length; the force on the pulled grip and the shear at the centre along the way.
//!
//! The mesh follows the yarns: diamonds whose sides run along them (rhombi when the width and
//! length are not a whole number of cells apart), halved into triangles along the edges, so
//! that inextensible yarns do not lock it. The specimen stays in its plane (z fixed).
//!
//! The ideal kinematics (inextensible, pin-jointed yarns; `src/guide/verification.md`): the centre's
//! shear `γ = π/2 − 2 acos((H − W + d) / (√2 (H − W)))` at a grip displacement `d`, and the
//! force of a shear law from the energy balance `F dd = M(γ) A_c dγ + M(γ/2) A_h dγ/2`, with
//! `A_c = W (H − 3W/2)` and `A_h = W²`.

use std::ops::ControlFlow;

use crate::core::fabric::law::{CellLaw, CellParams};
use crate::core::fabric::shear::ShearLaw;
use crate::core::membrane::mesh::Mesh;
use crate::core::solver::{
    Failure, LinearPrescribed, Model, NoNodalTerms, Prescribed, Solver, SolverOptions,
};

/// A bias-extension test.
#[derive(Clone, Debug, PartialEq)]
pub struct BiasProblem {
    pub fabric: CellParams,
    pub shear: Option<ShearLaw>,
    /// Free length between the grips `H` and width `W`, mm.
    pub length: f64,
    pub width: f64,
    /// Largest grip displacement, mm.
    pub stroke: f64,
    /// Target element size along the yarns, mm.
    pub element_size: f64,
    /// Points of the curve (equal displacement increments).
    pub points: usize,
    pub solver: SolverOptions,
    /// The width of the toe rounding the yarns' slack/taut kink, a yarn strain
    /// ([`crate::core::fabric::toe`]; 0 is the paper's kink; [`BIAS_TOE_STRAIN`] by default).
    pub toe_strain: f64,
}

/// The bias test's toe ([`BiasProblem::toe_strain`]): a tenth of the drawings'. Every yarn of
/// the specimen starts on the kink, and with it the first increments chatter for minutes (the
/// 300 × 150 mm specimen to 55 mm: 95 s with the kink, 3.3 s with this toe); at this width the
/// curve moves by 0.04° of shear and 0.4 % of force at its end (measured in
/// `guide::shear_law`), where the drawings' 10⁻³ moves it by 0.3° and 3 %.
pub const BIAS_TOE_STRAIN: f64 = 1e-4;

/// Why a bias test has no answer.
#[derive(Clone, Debug, PartialEq)]
pub enum BiasError {
    /// The paper's fabric (no shear law) trellises freely: the test's force is zero until the
    /// yarns jam, and its shape is not unique.
    NoShearStiffness,
    /// The specimen is not more than 1.5 times as long as it is wide, so it has no central
    /// zone (its area W (H − 3W/2) is not positive).
    TooShort {
        length: f64,
        width: f64,
    },
    /// The stroke reaches or passes the ideal kinematics' end (the central yarns aligned).
    StrokeTooLong {
        stroke: f64,
        limit: f64,
    },
    BadElement(crate::core::solver::BadElement),
}

impl std::fmt::Display for BiasError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BiasError::NoShearStiffness => write!(
                f,
                "the fabric has no in-plane shear stiffness (the paper's model): a bias specimen \
                 trellises freely, with no force until its yarns jam; give it a shear law, \
                 fabric.shear_moment = [k1, k3, k5]"
            ),
            BiasError::TooShort { length, width } => write!(
                f,
                "a bias specimen {length} mm long and {width} mm wide has no central zone: \
                 expected a length more than 1.5 times the width (usually twice)"
            ),
            BiasError::StrokeTooLong { stroke, limit } => write!(
                f,
                "a stroke of {stroke} mm reaches the end of the ideal kinematics at {limit:.1} mm \
                 ((√2 − 1)(H − W), where the central yarns align): expected less"
            ),
            BiasError::BadElement(e) => write!(f, "{e}"),
        }
    }
}

/// What came of a bias test.
#[derive(Clone, Debug)]
pub struct BiasResult {
    /// Grip displacement (mm), force on the pulled grip (N) and the centre's shear (°) at each
    /// point reached, from 0.
    pub displacement_mm: Vec<f64>,
    pub force_n: Vec<f64>,
    pub shear_centre_deg: Vec<f64>,
    /// Why the curve stops short of the stroke, if it does.
    pub failure: Option<Failure>,
    pub mesh: Mesh,
    /// Final positions and each element's shear (°).
    pub positions: Vec<[f64; 3]>,
    pub shear_deg: Vec<f64>,
    pub newton_iterations: u32,
}

/// The ideal central shear (rad) at a grip displacement `d` of an `h × w` specimen.
pub fn ideal_shear(h: f64, w: f64, d: f64) -> f64 {
    let x = ((h - w + d) / (std::f64::consts::SQRT_2 * (h - w))).clamp(-1.0, 1.0);
    std::f64::consts::FRAC_PI_2 - 2.0 * x.acos()
}

/// The ideal force (N) of shear law `law` at a grip displacement `d` (the energy balance).
pub fn ideal_force(law: &ShearLaw, h: f64, w: f64, d: f64) -> f64 {
    ideal_force_of(&|g| law.moment(g), h, w, d)
}

/// The ideal force (N) of any moment per unit area `m(γ)` at a grip displacement `d`:
/// `F = m(γ) A_c γ' + m(γ/2) A_h γ'/2`, linear in `m` (the fit's basis is `m = γʲ`).
pub fn ideal_force_of(m: &dyn Fn(f64) -> f64, h: f64, w: f64, d: f64) -> f64 {
    let (g, dg) = ideal_shear_rate(h, w, d);
    let (ac, ah) = (w * (h - 1.5 * w), w * w);
    m(g) * ac * dg + m(g / 2.0) * ah * dg / 2.0
}

/// The ideal central shear (rad) and its rate `dγ/dd` (rad/mm).
pub fn ideal_shear_rate(h: f64, w: f64, d: f64) -> (f64, f64) {
    let s = std::f64::consts::SQRT_2 * (h - w);
    let x = ((h - w + d) / s).min(1.0 - 1e-12);
    (ideal_shear(h, w, d), 2.0 / (s * (1.0 - x * x).sqrt()))
}

/// The largest displacement of the ideal kinematics, mm.
pub fn kinematic_limit(h: f64, w: f64) -> f64 {
    (std::f64::consts::SQRT_2 - 1.0) * (h - w)
}

/// The specimen's mesh along the yarns (±45°): node `(p, q)` at `(p ax/2, q ay/2)` for `p + q`
/// even; a diamond around each `(P, Q)` with `P + Q` odd, halved on the edges.
pub fn specimen_mesh(h: f64, w: f64, element_size: f64) -> Mesh {
    let diagonal = element_size * std::f64::consts::SQRT_2;
    let m = ((w / diagonal).round() as usize).max(2);
    // The same diagonal across and along (square diamonds, sides along the yarns) where the
    // length allows: exactly when H/W is a ratio of small whole numbers.
    let n = ((h * m as f64 / w).round() as usize).max(m + 1);
    let (ax, ay) = (h / n as f64, w / m as f64);
    let (np, nq) = (2 * n, 2 * m);
    let mut id = vec![usize::MAX; (np + 1) * (nq + 1)];
    let mut nodes = Vec::new();
    for q in 0..=nq {
        for p in 0..=np {
            if (p + q) % 2 == 0 {
                id[q * (np + 1) + p] = nodes.len();
                nodes.push([p as f64 * ax / 2.0, q as f64 * ay / 2.0, 0.0]);
            }
        }
    }
    let at = |p: isize, q: isize| -> Option<usize> {
        (p >= 0 && q >= 0 && p <= np as isize && q <= nq as isize)
            .then(|| id[q as usize * (np + 1) + p as usize])
    };
    let mut quads = Vec::new();
    for cq in 0..=nq as isize {
        for cp in 0..=np as isize {
            if (cp + cq) % 2 == 0 {
                continue;
            }
            // Bottom, right, top, left: counter-clockwise; a missing corner halves the diamond.
            let corners = [
                at(cp, cq - 1),
                at(cp + 1, cq),
                at(cp, cq + 1),
                at(cp - 1, cq),
            ];
            let inside: Vec<usize> = corners.iter().flatten().copied().collect();
            match inside.len() {
                4 => quads.push([inside[0], inside[1], inside[2], inside[3]]),
                3 => quads.push([inside[0], inside[1], inside[2], inside[2]]),
                _ => {}
            }
        }
    }
    let s = std::f64::consts::FRAC_1_SQRT_2;
    Mesh {
        nodes,
        quads,
        yarns: Some([[s, s, 0.0], [s, -s, 0.0]]),
        grid: None,
    }
}

impl BiasProblem {
    /// Checks the test before any solving.
    pub fn check(&self) -> Result<(), BiasError> {
        if self.shear.is_none() {
            return Err(BiasError::NoShearStiffness);
        }
        if self.length <= 1.5 * self.width {
            return Err(BiasError::TooShort {
                length: self.length,
                width: self.width,
            });
        }
        let limit = kinematic_limit(self.length, self.width);
        if self.stroke >= limit {
            return Err(BiasError::StrokeTooLong {
                stroke: self.stroke,
                limit,
            });
        }
        Ok(())
    }

    /// Pulls the specimen to the stroke in `points` equal increments, each solved from the
    /// last; `progress` receives the fraction of the stroke reached.
    pub fn solve(&self, progress: &mut dyn FnMut(f64)) -> Result<BiasResult, BiasError> {
        self.solve_until(&mut |f| {
            progress(f);
            ControlFlow::Continue(())
        })
    }

    /// [`BiasProblem::solve`], told the fraction of the stroke after every converged load step;
    /// `ControlFlow::Break` stops the pull there (the curve so far, `Failure::Stopped`).
    pub fn solve_until(
        &self,
        progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
    ) -> Result<BiasResult, BiasError> {
        self.check()?;
        let mesh = specimen_mesh(self.length, self.width, self.element_size);
        let (fixed, pulled) = grip_dofs(&mesh, self.length);
        let law = CellLaw::new(self.fabric)
            .with_shear(self.shear)
            .with_toe(self.toe_strain);
        let mut model = Model::new(mesh.clone(), law, &fixed).map_err(BiasError::BadElement)?;
        let centre = centre_elements(&mesh, self.length, self.width);
        let mut result = BiasResult {
            displacement_mm: vec![0.0],
            force_n: vec![0.0],
            shear_centre_deg: vec![0.0],
            failure: None,
            mesh,
            positions: Vec::new(),
            shear_deg: Vec::new(),
            newton_iterations: 0,
        };
        let points = self.points.max(2);
        // The grips: every fixed dof stays, the pulled ones move by the segment's displacement.
        let at_full_load = (fixed.iter())
            .map(|d| f64::from(u8::from(pulled.binary_search(d).is_ok())))
            .collect();
        let grips = LinearPrescribed {
            at_full_load,
            dofs: fixed,
        };
        let mut u_before: Option<Vec<f64>> = None;
        let mut options = self.solver.clone();
        options.initial_step = 1.0;
        options.max_step = 1.0;
        for k in 1..=points {
            let d = |k: usize| self.stroke * k as f64 / points as f64;
            let segment = Segment {
                grips: &grips,
                from: d(k - 1),
                to: d(k),
                stroke: self.stroke,
            };
            // The secant predictor: the last increment again (a segment that fails from it is
            // solved again from the last converged state).
            let (u_now, crimp_now) = (model.u.clone(), model.crimp.clone());
            if let Some(before) = &u_before {
                for (i, u) in model.u.iter_mut().enumerate() {
                    *u += u_now[i] - before[i];
                }
            }
            let mut solved = if k == 1 {
                first_segment(&mut model, &options, &segment, &mut result, progress)
            } else {
                solve_segment(&mut model, &options, &segment, &mut result, progress)
            };
            let stopped = matches!(solved, Err(Failure::Stopped { .. }));
            if solved.is_err() && !stopped && u_before.is_some() {
                model.u = u_now.clone();
                model.crimp = crimp_now;
                solved = solve_segment(&mut model, &options, &segment, &mut result, progress);
            }
            if let Err(failure) = solved {
                result.failure = Some(failure);
                break;
            }
            u_before = Some(u_now);
            record(&mut model, &mut result, d(k), &pulled, &centre);
        }
        result.positions = model.positions();
        result.shear_deg = model.shear_angles_deg();
        Ok(result)
    }
}

/// The constrained dofs of the specimen (every node's z; both in-plane dofs at the grips, the
/// ends x = 0 and x = length) and those pulled (x at x = length), each sorted.
fn grip_dofs(mesh: &Mesh, length: f64) -> (Vec<usize>, Vec<usize>) {
    let tol = 1e-9 * length;
    let (mut fixed, mut pulled) = (Vec::new(), Vec::new());
    for (i, p) in mesh.nodes.iter().enumerate() {
        fixed.push(3 * i + 2);
        if p[0] < tol || p[0] > length - tol {
            fixed.extend([3 * i, 3 * i + 1]);
        }
        if p[0] > length - tol {
            pulled.push(3 * i);
        }
    }
    fixed.sort_unstable();
    (fixed, pulled)
}

/// The first segment. It starts with every yarn on the law's slack/taut kink, where the active
/// set chatters (thousands of yarns flip per iteration): it may need many small steps before
/// the yarns settle. Solved as the others (with more steps allowed); should that fail, to a
/// looser floor first (a yarn strain of 1e-5), then again to the usual one from there.
fn first_segment(
    model: &mut Model,
    options: &SolverOptions,
    segment: &Segment<'_>,
    result: &mut BiasResult,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> Result<(), Failure> {
    let (u_now, crimp_now) = (model.u.clone(), model.crimp.clone());
    let mut strict = options.clone();
    strict.max_steps = strict.max_steps.max(1500);
    let first = solve_segment(model, &strict, segment, result, progress);
    if first.is_ok() || matches!(first, Err(Failure::Stopped { .. })) {
        return first;
    }
    model.u = u_now;
    model.crimp = crimp_now;
    let mut loose = options.clone();
    loose.tol_floor = 1e-5;
    loose.max_steps = loose.max_steps.max(5000);
    solve_segment(model, &loose, segment, result, progress)?;
    let again = Segment {
        grips: segment.grips,
        from: segment.to,
        to: segment.to,
        stroke: segment.stroke,
    };
    solve_segment(model, options, &again, result, progress)
}

/// The pull force and the centre's mean shear of the converged state at grip displacement
/// `d_mm`, appended to the curve.
fn record(
    model: &mut Model,
    result: &mut BiasResult,
    d_mm: f64,
    pulled: &[usize],
    centre: &[usize],
) {
    model.evaluate_elements(false, false);
    let f = model.internal_force();
    let shear = model.shear_angles_deg();
    result.displacement_mm.push(d_mm);
    result.force_n.push(pulled.iter().map(|&d| f[d]).sum());
    let mean = centre.iter().map(|&e| shear[e]).sum::<f64>() / centre.len() as f64;
    result.shear_centre_deg.push(mean);
}

/// Solves one segment of the pull from the model's state; counts its Newton iterations.
fn solve_segment(
    model: &mut Model,
    options: &SolverOptions,
    segment: &Segment<'_>,
    result: &mut BiasResult,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> Result<(), Failure> {
    let mut solver = Solver::new(model, options.clone());
    let (from, to, stroke) = (segment.from, segment.to, segment.stroke);
    let solved = solver.solve(segment, &mut NoNodalTerms, &mut |l| {
        progress((from + l * (to - from)) / stroke)
    });
    result.newton_iterations += solver.stats.newton_iterations;
    solved
}

/// The grips' displacements from `from` to `to` (mm) along one solve's load path: the pulled
/// dofs move by `from + λ (to − from)`, the rest stay.
struct Segment<'a> {
    grips: &'a LinearPrescribed,
    from: f64,
    to: f64,
    /// The whole pull, mm (for the progress's fraction).
    stroke: f64,
}

impl Prescribed for Segment<'_> {
    fn dofs(&self) -> &[usize] {
        &self.grips.dofs
    }
    fn values(&self, lambda: f64, out: &mut [f64]) {
        let d = self.from + lambda * (self.to - self.from);
        for (o, v) in out.iter_mut().zip(&self.grips.at_full_load) {
            *o = d * v;
        }
    }
}

/// The elements whose centres lie within a cell's reach of the specimen's centre (at least
/// one): where the central zone's shear is read.
fn centre_elements(mesh: &Mesh, h: f64, w: f64) -> Vec<usize> {
    let centre = |q: &[usize; 4]| {
        let mut c = [0.0; 2];
        for &n in q {
            c[0] += 0.25 * mesh.nodes[n][0];
            c[1] += 0.25 * mesh.nodes[n][1];
        }
        c
    };
    let dist = |q: &[usize; 4]| {
        let c = centre(q);
        ((c[0] - h / 2.0).powi(2) + (c[1] - w / 2.0).powi(2)).sqrt()
    };
    let nearest = mesh.quads.iter().map(dist).fold(f64::INFINITY, f64::min);
    let reach = (0.1 * w).max(nearest + 1e-9);
    (0..mesh.quads.len())
        .filter(|&e| dist(&mesh.quads[e]) <= reach)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_specimen_mesh_covers_the_rectangle_with_diamonds_and_edge_triangles() {
        let mesh = specimen_mesh(230.0, 115.0, 5.0);
        // Area: the sum of the (collapsed) quads' shoelace areas.
        let area: f64 = mesh
            .quads
            .iter()
            .map(|q| {
                let p = q.map(|n| mesh.nodes[n]);
                0.5 * (0..4)
                    .map(|i| p[i][0] * p[(i + 1) % 4][1] - p[(i + 1) % 4][0] * p[i][1])
                    .sum::<f64>()
            })
            .sum();
        assert!((area - 230.0 * 115.0).abs() < 1e-6, "{area}");
        assert!(
            mesh.nodes
                .iter()
                .all(|p| p[0] >= 0.0 && p[0] <= 230.0 && p[1] >= 0.0 && p[1] <= 115.0)
        );
    }
}
