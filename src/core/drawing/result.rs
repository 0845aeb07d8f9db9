//! What a drawing found on the solved part of the blank, and whether it can be trusted.

use super::LeftOut;
use super::failure::DrawingFailure;
use crate::core::membrane::mesh::Mesh;
use crate::core::solver::SolveStats;

/// The largest penetration of a node into a tool a sound result may have, as a fraction of the
/// element size.
pub const PENETRATION_LIMIT: f64 = 0.05;

/// The largest share of the punch's work that forces left out of balance may have done in a
/// sound result.
pub const UNBALANCED_WORK_LIMIT: f64 = 0.01;

/// Why a converged result cannot be trusted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unsound {
    /// A node sank into a tool by more than [`PENETRATION_LIMIT`] of the element size.
    Penetration { mm: f64, limit_mm: f64 },
    /// Forces out of balance did more than [`UNBALANCED_WORK_LIMIT`] of the punch's work.
    Unbalanced {
        share: f64,
        limit: f64,
        punch_work_nmm: f64,
    },
}

impl std::fmt::Display for Unsound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unsound::Penetration { mm, limit_mm } => write!(
                f,
                "the fabric sank {mm:.3} mm into a tool, more than {:.0} % of the element \
                 size ({limit_mm:.3} mm): raise numerics.penalty_factor",
                100.0 * PENETRATION_LIMIT
            ),
            // Over the punch's work, the share is no longer a useful number: say the works.
            Unsound::Unbalanced {
                share,
                limit,
                punch_work_nmm,
            } if *share > 1.0 => write!(
                f,
                "forces out of balance did {:.3e} N·mm of work, more than the punch's own \
                 {punch_work_nmm:.3e} N·mm (at most {:.0} % of it is sound): the punch does too \
                 little work for the solver's tolerance to resolve",
                share * punch_work_nmm,
                100.0 * limit
            ),
            Unsound::Unbalanced { share, limit, .. } => write!(
                f,
                "forces out of balance did {:.1} % of the punch's work (at most {:.0} % is \
                 sound)",
                100.0 * share,
                100.0 * limit
            ),
        }
    }
}

/// The solved part of the blank and what was found on it.
#[derive(Clone, Debug)]
pub struct DrawingResult {
    pub converged: bool,
    /// Why the run stopped short, if it did.
    pub failure: Option<DrawingFailure>,
    /// Whether the mesh is a quarter (x ≥ 0, y ≥ 0) to be mirrored for pictures.
    pub quarter: bool,
    pub mesh: Mesh,
    /// Target element size, mm.
    pub element_size_mm: f64,
    /// The woven cell's mean side, mm: the radius of the neighbourhood the peaks are taken over
    /// ([`DrawingResult::max_shear`], [`DrawingResult::max_tension_n`]).
    pub cell_mm: f64,
    /// Final nodal positions, mm.
    pub positions: Vec<[f64; 3]>,
    /// Shear angle of each element, degrees (signed).
    pub shear_deg: Vec<f64>,
    /// Mean warp and weft tensions of each element, N per yarn.
    pub t11_n: Vec<f64>,
    pub t22_n: Vec<f64>,
    /// Largest yarn tension of each element, N.
    pub tension_max_n: Vec<f64>,
    /// Contact status of each node: 0 free, 1 punch, 2 die, 3 die and holder.
    pub contact: Vec<u8>,
    /// The wrinkle amplitude through each node, mm ([`crate::core::wrinkles::amplitude`]), when the fabric
    /// has bending; `None` for the paper's membrane, which has no wrinkles to show.
    pub wrinkle_mm: Option<Vec<f64>>,
    /// Punch stroke reached, mm.
    pub stroke_reached_mm: f64,
    /// Punch force on the whole blank, N, and its history against the stroke (mm, N).
    pub punch_force_n: f64,
    pub force_history: Vec<(f64, f64)>,
    /// Largest penetration of a node into a tool, mm.
    pub penetration_mm: f64,
    /// Largest draw-in of the blank's edge (inward plan displacement), mm.
    pub draw_in_mm: f64,
    /// Free dofs of the solved model.
    pub dofs: usize,
    pub stats: SolveStats,
    /// Work of the punch on the blank (the force history integrated over the stroke), N·mm.
    pub punch_work_nmm: f64,
    /// Work done by forces out of balance at the converged steps over the punch's work: what of
    /// the punch's work is not the paper's model. The stabilisation acts on the Newton
    /// corrections only, so a converged state carries none of it; what is left is the residual
    /// within the tolerance. (`run --json` calls it `stabilisation_work_share`.)
    pub unbalanced_work_share: f64,
    /// Terms the scene did not need and that were not built.
    pub left_out: Vec<LeftOut>,
}

impl DrawingResult {
    /// The blank as meshed, before any stroke: no field, no force, not converged.
    pub fn at_rest(mesh: Mesh, quarter: bool, element_size_mm: f64, cell_mm: f64) -> Self {
        let (ne, nn) = (mesh.quads.len(), mesh.nodes.len());
        DrawingResult {
            converged: false,
            failure: None,
            quarter,
            element_size_mm,
            cell_mm,
            positions: mesh.nodes.clone(),
            shear_deg: vec![0.0; ne],
            t11_n: vec![0.0; ne],
            t22_n: vec![0.0; ne],
            tension_max_n: vec![0.0; ne],
            contact: vec![0; nn],
            wrinkle_mm: None,
            stroke_reached_mm: 0.0,
            punch_force_n: 0.0,
            force_history: Vec::new(),
            penetration_mm: 0.0,
            draw_in_mm: 0.0,
            dofs: 0,
            stats: SolveStats::default(),
            punch_work_nmm: 0.0,
            unbalanced_work_share: 0.0,
            left_out: Vec::new(),
            mesh,
        }
    }

    /// The peak shear the verdict compares with the locking angle: the largest mean |shear|
    /// (degrees) over a disc of one woven cell ([`DrawingResult::cell_mm`]) in the undeformed
    /// blank, and the element at the disc's centre (see `peak.rs`). Unlike the largest element
    /// value it does not hang on how finely a corner happens to be meshed.
    pub fn max_shear(&self) -> (usize, f64) {
        self.neighbourhood_peak(&self.shear_deg, self.cell_mm)
    }

    /// Both peaks over one woven cell with one neighbour search: `[max_shear, max tension]`,
    /// each the element at the disc's centre and the peak.
    pub fn cell_peaks(&self) -> [(usize, f64); 2] {
        let p = self.neighbourhood_peaks(&[&self.shear_deg, &self.tension_max_n], self.cell_mm);
        [p[0], p[1]]
    }

    /// The element with the largest absolute shear, and that shear (degrees): the peak at the
    /// scale of one element, which keeps rising as the mesh is refined.
    pub fn max_shear_element(&self) -> (usize, f64) {
        self.shear_deg
            .iter()
            .enumerate()
            .map(|(e, s)| (e, s.abs()))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
    }

    /// Centre of element `e` in the final configuration, mm.
    pub fn element_centre(&self, e: usize) -> [f64; 3] {
        let mut c = [0.0; 3];
        for &n in &self.mesh.quads[e] {
            for m in 0..3 {
                c[m] += 0.25 * self.positions[n][m];
            }
        }
        c
    }

    /// Share of the blank's initial area whose shear exceeds `limit_deg`, %.
    pub fn area_over_limit_pct(&self, limit_deg: f64) -> f64 {
        let mut over = 0.0;
        let mut total = 0.0;
        for (e, q) in self.mesh.quads.iter().enumerate() {
            let a = quad_area(&q.map(|n| self.mesh.nodes[n]));
            total += a;
            if self.shear_deg[e].abs() > limit_deg {
                over += a;
            }
        }
        if total > 0.0 {
            100.0 * over / total
        } else {
            0.0
        }
    }

    /// The peak yarn tension the verdict compares with the breaking tension, N: the largest
    /// mean of the elements' largest yarn tensions over a disc of one woven cell, as
    /// [`DrawingResult::max_shear`].
    pub fn max_tension_n(&self) -> f64 {
        self.neighbourhood_peak(&self.tension_max_n, self.cell_mm).1
    }

    /// The largest yarn tension of any element, N.
    pub fn max_tension_element_n(&self) -> f64 {
        self.tension_max_n.iter().fold(0.0, |a, &b| a.max(b))
    }

    /// The largest wrinkle amplitude, mm, and where (the final position of a node of its span,
    /// mm), when the fabric has bending ([`DrawingResult::wrinkle_mm`]).
    pub fn max_wrinkle(&self) -> Option<(f64, [f64; 3])> {
        let w = self.wrinkle_mm.as_ref()?;
        let (i, a) = w
            .iter()
            .enumerate()
            .fold((0, 0.0), |a, (i, &v)| if v > a.1 { (i, v) } else { a });
        Some((a, self.positions.get(i).copied().unwrap_or([0.0; 3])))
    }

    /// Why this result cannot be trusted even though it converged (empty: it can).
    pub fn unsound(&self) -> Vec<Unsound> {
        let mut why = Vec::new();
        let limit_mm = PENETRATION_LIMIT * self.element_size_mm;
        if self.penetration_mm > limit_mm {
            why.push(Unsound::Penetration {
                mm: self.penetration_mm,
                limit_mm,
            });
        }
        if self.unbalanced_work_share > UNBALANCED_WORK_LIMIT {
            why.push(Unsound::Unbalanced {
                share: self.unbalanced_work_share,
                limit: UNBALANCED_WORK_LIMIT,
                punch_work_nmm: self.punch_work_nmm,
            });
        }
        why
    }
}

fn quad_area(x: &[[f64; 3]; 4]) -> f64 {
    let d1 = [x[2][0] - x[0][0], x[2][1] - x[0][1], x[2][2] - x[0][2]];
    let d2 = [x[3][0] - x[1][0], x[3][1] - x[1][1], x[3][2] - x[1][2]];
    let c = [
        d1[1] * d2[2] - d1[2] * d2[1],
        d1[2] * d2[0] - d1[0] * d2[2],
        d1[0] * d2[1] - d1[1] * d2[0],
    ];
    0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
}
