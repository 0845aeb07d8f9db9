//! A tool given as a closed triangle surface (read from STL by the layers above), placed in
//! the analytic tools' frame: a punch with its lowest point in the blank's plane z = 0 (it
//! moves down by the stroke), a die with its top face in z = 0 (where the holder presses).
//! The fabric meets it through [`SampledDistance`] (smooth), the holder through the die's
//! [`Flange`].

use super::flange::Flange;
use super::sampled::SampledDistance;
use super::surface::TriSurface;

/// How far a punch's lowest point or a die's highest may lie from z = 0, mm.
pub const PLACEMENT_TOL_MM: f64 = 0.05;

/// How far into the stroke the punch is checked for starting inside the die, mm.
pub const START_MM: f64 = 0.1;

/// What a mesh tool is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Punch,
    Die,
}

/// Why a mesh tool, or a pair of them, cannot be used as placed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlacementError {
    #[error(
        "the punch's lowest point is at z = {lowest_mm:.4} mm; expected z = 0 (where it first \
         touches the blank) within {PLACEMENT_TOL_MM} mm: move the punch in z"
    )]
    PunchNotAtBlank { lowest_mm: f64 },
    #[error(
        "the die's highest point is at z = {highest_mm:.4} mm; expected its top face (where the \
         holder presses the blank) in z = 0 within {PLACEMENT_TOL_MM} mm: move the die in z"
    )]
    DieNotAtFace { highest_mm: f64 },
    #[error(
        "the die has no face in z = 0 (no triangle within 0.01 mm of z = 0 facing up): the \
         holder has nothing to press the blank on"
    )]
    NoFace,
    #[error(
        "the punch starts inside the die (or on its face, where it would pinch the blank): \
         {START_MM} mm into the stroke its point ({:.2}, {:.2}, {:.2}) mm is {depth_mm:.3} mm \
         deep in the die's material", at[0], at[1], at[2]
    )]
    PunchInsideDie { at: [f64; 3], depth_mm: f64 },
    #[error(
        "the punch runs into the die before the end of the stroke: at {stroke_mm} mm of \
         stroke its point ({:.2}, {:.2}, {:.2}) mm is {depth_mm:.3} mm deep in the die's \
         material (does its plan fit the die opening?)", at[0], at[1], at[2]
    )]
    PunchHitsDie {
        stroke_mm: f64,
        at: [f64; 3],
        depth_mm: f64,
    },
}

/// A rigid tool from a triangle surface.
pub struct MeshTool {
    pub role: Role,
    /// What the user calls it (its file), for messages.
    pub name: String,
    pub triangles: usize,
    pub distance: SampledDistance,
    /// The face the holder presses on (dies only).
    pub flange: Option<Flange>,
    pub bounds: ([f64; 3], [f64; 3]),
    vertices: Vec<[f64; 3]>,
    fingerprint: u64,
}

impl std::fmt::Debug for MeshTool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "MeshTool({:?} {}, {} triangles, lattice {} mm)",
            self.role,
            self.name,
            self.triangles,
            self.distance.spacing()
        )
    }
}

/// Two mesh tools are the same tool when their role, surface and lattice are.
impl PartialEq for MeshTool {
    fn eq(&self, other: &Self) -> bool {
        self.role == other.role
            && self.fingerprint == other.fingerprint
            && self.distance.spacing() == other.distance.spacing()
    }
}

fn fingerprint(surface: &TriSurface) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for v in &surface.vertices {
        v.map(f64::to_bits).hash(&mut h);
    }
    surface.triangles.hash(&mut h);
    h.finish()
}

impl MeshTool {
    /// The tool `surface` (checked: [`TriSurface::check`]) as a `role`, its distance sampled
    /// every `spacing` mm and exact within `band` mm of the surface; refused when misplaced.
    pub fn new(
        role: Role,
        name: &str,
        surface: &TriSurface,
        spacing: f64,
        band: f64,
    ) -> Result<MeshTool, PlacementError> {
        let bounds = surface.bounds();
        let flange = match role {
            Role::Punch => {
                if bounds.0[2].abs() > PLACEMENT_TOL_MM {
                    return Err(PlacementError::PunchNotAtBlank {
                        lowest_mm: bounds.0[2],
                    });
                }
                None
            }
            Role::Die => {
                if bounds.1[2].abs() > PLACEMENT_TOL_MM {
                    return Err(PlacementError::DieNotAtFace {
                        highest_mm: bounds.1[2],
                    });
                }
                Some(Flange::of(surface, spacing).ok_or(PlacementError::NoFace)?)
            }
        };
        Ok(MeshTool {
            role,
            name: name.to_string(),
            triangles: surface.triangles.len(),
            distance: SampledDistance::new(surface, spacing, band, band + 4.0 * spacing),
            flange,
            bounds,
            vertices: surface.vertices.clone(),
            fingerprint: fingerprint(surface),
        })
    }

    /// The tool's surface as read.
    pub fn surface(&self) -> TriSurface {
        TriSurface {
            vertices: self.vertices.clone(),
            triangles: self.distance.exact().triangles().to_vec(),
        }
    }

    /// The smallest radius of curvature among the surface's vertices within the box
    /// `[lo, hi]` (mm), from how fast the vertex normals turn along each edge,
    /// `|n_a − n_b| / |a − b|` (exact on a tessellated sphere). The 0.5 % quantile is taken so
    /// that a few slivers do not decide it; `f64::INFINITY` where the surface is flat.
    pub fn smallest_radius_mm(&self, lo: [f64; 3], hi: [f64; 3]) -> f64 {
        let within = |p: &[f64; 3]| (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a]);
        let exact = self.distance.exact();
        let mut curvatures: Vec<f64> = Vec::new();
        for t in exact.triangles() {
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                if a > b || !within(&self.vertices[a]) || !within(&self.vertices[b]) {
                    continue;
                }
                let (na, nb) = (exact.vertex_normal(a), exact.vertex_normal(b));
                let (pa, pb) = (self.vertices[a], self.vertices[b]);
                let dn = (0..3).map(|i| (na[i] - nb[i]).powi(2)).sum::<f64>().sqrt();
                let dx = (0..3).map(|i| (pa[i] - pb[i]).powi(2)).sum::<f64>().sqrt();
                if dx > 0.0 {
                    curvatures.push(dn / dx);
                }
            }
        }
        if curvatures.is_empty() {
            return f64::INFINITY;
        }
        curvatures.sort_by(|a, b| b.total_cmp(a));
        let k = curvatures[curvatures.len() / 200];
        if k > 0.0 { 1.0 / k } else { f64::INFINITY }
    }

    /// Refuses a punch that starts inside the die or runs into it within `stroke_mm`: each of
    /// its vertices below the blank's plane `START_MM` into the stroke and at ¼, ½, ¾ and the
    /// whole stroke is checked against the die's exact distance (deeper than
    /// `PLACEMENT_TOL_MM` is a clash).
    pub fn check_pair(
        punch: &MeshTool,
        die: &MeshTool,
        stroke_mm: f64,
    ) -> Result<(), PlacementError> {
        for k in 0..=4 {
            let s = if k == 0 {
                START_MM.min(stroke_mm)
            } else {
                stroke_mm * k as f64 / 4.0
            };
            let (dlo, dhi) = die.bounds;
            // The die's smooth distance: exact near its surface, a bound of the right sign
            // farther (cheap where most vertices are, far from it).
            let depth = |v: &[f64; 3]| {
                let p = [v[0], v[1], v[2] - s];
                let outside = p[2] > PLACEMENT_TOL_MM
                    || (0..3).any(|a| p[a] < dlo[a] - 1.0 || p[a] > dhi[a] + 1.0);
                let d = if outside {
                    f64::INFINITY
                } else {
                    die.distance.evaluate(p, false).d
                };
                (p, d)
            };
            use rayon::prelude::*;
            let worst = punch
                .vertices
                .par_iter()
                .map(depth)
                .filter(|(_, d)| *d < -PLACEMENT_TOL_MM)
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((at, d)) = worst {
                return Err(if k == 0 {
                    PlacementError::PunchInsideDie { at, depth_mm: -d }
                } else {
                    PlacementError::PunchHitsDie {
                        stroke_mm: s,
                        at,
                        depth_mm: -d,
                    }
                });
            }
        }
        Ok(())
    }
}
