//! The Euler strip: a strip of fabric (warp along it) clamped flat at both ends and shortened
//! by `Δ`, the buckling check of bending stiffness with compressive yarns.
//!
//! The strip runs from `x = −h` to `x = L + h` (`h` the element length): the two rows of nodes
//! at each end are held, so the clamps are flat and the free length is `L`; the end at
//! `x = L` moves by `−Δ` along x in load steps. A buckling problem needs a trigger: a small
//! lateral pressure `q` along −z on the whole strip, given by the sag it alone would cause at
//! mid-length, `q L⁴/(384 B)` (`trigger_sag_mm`), which favours the first (symmetric) mode as
//! a seeded imperfection of that shape would. (An imperfection in the initial mesh would be
//! bent straight again: the hinges' rest state is a straight line.) The closed forms (`src/guide/bending.md`): it stays
//! nearly flat until the end force reaches `4π²BW/L²`, then buckles, the force staying near
//! that value and the amplitude `(2/π)√(L(Δ − Δc))`.

use crate::core::membrane::element::GeometryError;
use crate::core::solver::{BadElement, Failure, Model};
use crate::core::specimens::clamped::{ClampedStrip, Clamps};
use crate::core::specimens::strip::{self, DeadLoad};

/// A clamped–clamped strip shortened by its `shortening_mm`, its fabric's linear yarn law.
#[derive(Clone, Debug)]
pub(crate) struct EulerStripProblem {
    pub(crate) strip: ClampedStrip,
    /// The trigger: the mid-length sag the lateral pressure alone causes, mm.
    pub(crate) trigger_sag_mm: f64,
}

/// The curve of the shortening.
#[derive(Clone, Debug, Default)]
pub(crate) struct EulerStripResult {
    pub(crate) shortening_mm: Vec<f64>,
    /// The force on the moving clamp along −x (compression positive), N.
    pub(crate) force_n: Vec<f64>,
    /// The deflection at mid-length below the clamps' plane (mean over the width), mm.
    pub(crate) amplitude_mm: Vec<f64>,
    /// The wrinkle figure of the strip ([`crate::core::wrinkles::amplitude`], the clamps anchored), mm.
    pub(crate) wrinkle_mm: Vec<f64>,
    pub(crate) failure: Option<Failure>,
}

impl EulerStripProblem {
    /// Shortens the strip in `points` increments; each point solved from the last. An element
    /// that cannot be built (a size not positive) is the error.
    pub(crate) fn solve(&self) -> Result<EulerStripResult, BadElement> {
        let p = &self.strip;
        let (mesh, h) = strip::strip_mesh(p.length, p.width, p.element_size, 4, 1);
        let [n1, _] = mesh.grid.expect("a yarn grid");
        let column = |i: usize| i % (n1 + 1);
        let clamped = |c: usize| c <= 1 || c >= n1 - 1;
        let clamps = Clamps::new(
            mesh.nodes.len(),
            |i| clamped(column(i)),
            |i| column(i) >= n1 - 1,
        );
        // The strip's grid runs along its yarns: only a first element of no length (or not
        // finite) has no yarn lines.
        let degenerate = BadElement {
            element: 0,
            cause: GeometryError::Degenerate,
        };
        let mut hinges = crate::core::membrane::hinges::yarn_hinges(&mesh, p.bending_rigidity)
            .ok_or(degenerate)?;
        strip::stiffen_clamp_edges(&mut hinges, column, clamped);
        let mut model = Model::with_hinges(mesh.clone(), p.law(None), &clamps.held, hinges)?;
        let mut out = EulerStripResult {
            shortening_mm: vec![0.0],
            force_n: vec![0.0],
            amplitude_mm: vec![0.0],
            wrinkle_mm: vec![0.0],
            failure: None,
        };
        let q = self.trigger_sag_mm * 384.0 * p.bending_rigidity[0] / p.length.powi(4);
        let mut trigger = DeadLoad {
            force_z: crate::core::membrane::mesh::tributary_areas(&mesh)
                .iter()
                .map(|a| -q * a)
                .collect(),
            scaled: false,
        };
        let mid: Vec<usize> = (0..mesh.nodes.len())
            .filter(|&i| (mesh.nodes[i][0] - 0.5 * p.length).abs() < 0.5 * h + 1e-9)
            .collect();
        let anchored: Vec<bool> = (0..mesh.nodes.len()).map(|i| clamped(column(i))).collect();
        let at_point = |d: f64, force: f64, model: &Model| {
            let x = model.positions();
            let amp = -mid.iter().map(|&i| x[i][2]).sum::<f64>() / mid.len().max(1) as f64;
            out.shortening_mm.push(d);
            out.force_n.push(force);
            out.amplitude_mm.push(amp);
            let w = crate::core::wrinkles::amplitude::wrinkles(&mesh, &x, &anchored);
            out.wrinkle_mm.push(w.map_or(0.0, |w| w.max_mm));
        };
        out.failure = clamps.shorten(&mut model, p, &mut trigger, at_point);
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::fabric::law::CellParams;
    use crate::core::solver::SolverOptions;

    /// The Euler strip of the glass fabric (B = 0.08 N·mm per mm of width): 100 × 10 mm, 2 mm
    /// elements, shortened by 1 mm in ten points, with yarns `fraction` of C in compression and
    /// a trigger of `sag` mm.
    fn problem(fraction: f64, sag: f64) -> EulerStripProblem {
        let mut fabric = CellParams::PAPER_GLASS;
        fabric.undulation = false;
        EulerStripProblem {
            strip: ClampedStrip {
                fabric,
                bending_rigidity: [0.08, 0.08],
                compression: [fraction, fraction],
                length: 100.0,
                width: 10.0,
                element_size: 2.0,
                shortening_mm: 1.0,
                points: 10,
                solver: SolverOptions::default(),
            },
            trigger_sag_mm: sag,
        }
    }

    fn euler(fraction: f64, sag: f64) -> EulerStripResult {
        problem(fraction, sag).solve().unwrap()
    }

    #[test]
    fn a_strip_of_no_length_or_width_is_an_error_not_a_panic() {
        let mut p = problem(1e-5, 0.01);
        p.strip.length = 0.0;
        assert_eq!(p.solve().unwrap_err().cause, GeometryError::Degenerate);
        let mut p = problem(1e-5, 0.01);
        p.strip.width = 0.0;
        assert_eq!(p.solve().unwrap_err().cause, GeometryError::Degenerate);
    }

    #[test]
    fn the_euler_strip_stays_flat_to_the_critical_force_then_buckles_as_the_closed_form() {
        let (b, w, l) = (0.08, 10.0, 100.0);
        let critical = 4.0 * std::f64::consts::PI.powi(2) * b * w / (l * l);
        // Compressive yarns of 1e-5 C (0.38 N): the membrane's end force W Cc Δ/(L0 L) reaches
        // the critical force at Δc = 0.396 mm.
        let cc = 1e-5 * CellParams::PAPER_GLASS.c[0];
        let per_mm = w * cc / (CellParams::PAPER_GLASS.l0[1] * l);
        let delta_c = critical / per_mm;
        for sag in [0.01, 0.001] {
            let r = euler(1e-5, sag);
            assert!(r.failure.is_none(), "{:?}", r.failure);
            for i in 1..r.force_n.len() {
                let (d, f, a) = (r.shortening_mm[i], r.force_n[i], r.amplitude_mm[i]);
                if d < 0.8 * delta_c {
                    // Flat: the membrane's force, the trigger's sag barely amplified.
                    assert!((f / (per_mm * d) - 1.0).abs() < 0.01, "Δ {d}: {f} N");
                    assert!(a.abs() < 0.1, "Δ {d}: amplitude {a} mm before buckling");
                } else if d > 1.4 * delta_c {
                    let closed = 2.0 / std::f64::consts::PI * (l * (d - delta_c)).sqrt();
                    assert!(
                        (f / critical - 1.0).abs() < 0.03,
                        "Δ {d}: {f} N against {critical} N"
                    );
                    assert!(
                        (a / closed - 1.0).abs() < 0.1,
                        "Δ {d}: {a} mm against {closed} mm"
                    );
                }
            }
        }
    }

    #[test]
    fn stiffer_compression_buckles_sooner_to_the_same_plateau() {
        // 1e-2 C: Δc = 0.4 µm, so every point is past buckling.
        let r = euler(1e-2, 0.01);
        let critical = 4.0 * std::f64::consts::PI.powi(2) * 0.08 * 10.0 / 1e4;
        let last = r.force_n.len() - 1;
        assert!((r.force_n[last] / critical - 1.0).abs() < 0.03);
        let closed = 2.0 / std::f64::consts::PI * (100.0f64 * 1.0).sqrt();
        assert!((r.amplitude_mm[last] / closed - 1.0).abs() < 0.1);
    }

    /// The wrinkle figure (`core::wrinkles::amplitude`) measures the buckled strip's height from the clamps'
    /// chord: the closed form's amplitude past buckling, within 10 %, and nothing while flat.
    #[test]
    fn the_wrinkle_figure_of_the_euler_strip_is_its_amplitude() {
        let (b, w, l) = (0.08, 10.0, 100.0);
        let critical = 4.0 * std::f64::consts::PI.powi(2) * b * w / (l * l);
        let cc = 1e-5 * CellParams::PAPER_GLASS.c[0];
        let delta_c = critical / (w * cc / (CellParams::PAPER_GLASS.l0[1] * l));
        let r = euler(1e-5, 0.001);
        let mut checked = 0;
        for i in 1..r.wrinkle_mm.len() {
            let (d, wr) = (r.shortening_mm[i], r.wrinkle_mm[i]);
            if d < 0.8 * delta_c {
                assert!(wr < 0.05, "Δ {d}: wrinkle {wr} mm while flat");
            } else if d > 1.4 * delta_c {
                let closed = 2.0 / std::f64::consts::PI * (l * (d - delta_c)).sqrt();
                assert!(
                    (wr / closed - 1.0).abs() < 0.1,
                    "Δ {d}: {wr} mm against {closed} mm"
                );
                checked += 1;
            }
        }
        assert!(checked >= 3);
    }
}
