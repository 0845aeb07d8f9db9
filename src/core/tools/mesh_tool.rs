//! A tool given as a closed triangle surface (read from STL by the layers above), placed in
//! the analytic tools' frame: a punch with its lowest point in the blank's plane z = 0 (it
//! moves down by the stroke), a die with its top face in z = 0 (where the holder presses).
//! The fabric meets it through [`SampledDistance`] (smooth), the holder through the die's
//! [`Flange`].

use super::flange::{Flange, NoFlange};
use super::sampled::{Box3, EVERYWHERE, SampledDistance};
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
        "no part of the die's face in z = 0 lies under the blank or near it (x from {:.1} to \
         {:.1} mm, y from {:.1} to {:.1} mm): its opening is wider than the blank, and the \
         holder has nothing to press the blank on", near.0[0], near.1[0], near.0[1], near.1[1]
    )]
    FaceNotUnderBlank { near: ([f64; 3], [f64; 3]) },
    #[error(
        "its tables would take {total:.3e} bytes (its {part} {part_bytes:.3e}), over the \
         {limit:.3e} bytes a run may use"
    )]
    TooLarge {
        total: f64,
        part: &'static str,
        part_bytes: f64,
        limit: f64,
    },
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

/// Refuses a punch whose lowest point, or a die whose highest, is not in z = 0.
fn placed(role: Role, (lo, hi): Box3) -> Result<(), PlacementError> {
    match role {
        Role::Punch if lo[2].abs() > PLACEMENT_TOL_MM => {
            Err(PlacementError::PunchNotAtBlank { lowest_mm: lo[2] })
        }
        Role::Die if hi[2].abs() > PLACEMENT_TOL_MM => {
            Err(PlacementError::DieNotAtFace { highest_mm: hi[2] })
        }
        _ => Ok(()),
    }
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

/// 64-bit FNV-1a of the surface's vertices (their bits) and triangles: the same on every
/// platform and Rust version, so that it can be stored (a sweep's lock keeps it).
fn fingerprint(surface: &TriSurface) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for v in &surface.vertices {
        for x in v {
            eat(&x.to_bits().to_le_bytes());
        }
    }
    for t in &surface.triangles {
        for i in t {
            eat(&i.to_le_bytes());
        }
    }
    h
}

/// Where the fabric can be, in a tool's own frame, and the memory its tables may take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// The lattice and the face raster cover no more of the tool than this box, mm.
    pub reach: Box3,
    /// The bytes the tool's tables may take.
    pub budget_bytes: f64,
}

impl Limits {
    /// The whole tool, whatever it takes.
    pub const EVERYWHERE: Limits = Limits {
        reach: EVERYWHERE,
        budget_bytes: f64::INFINITY,
    };
}

/// About how many bytes the exact distance keeps per triangle: its corners, normals,
/// pseudonormals and the hierarchy's nodes.
const HIERARCHY_BYTES_PER_TRIANGLE: f64 = 400.0;

/// The bytes a tool's tables would take, part by part (named for messages), before any is
/// allocated: the exact distance's hierarchy, the lattice's page table and the samples the
/// fabric can visit, and a die's face raster.
pub fn footprint(
    role: Role,
    surface: &TriSurface,
    spacing: f64,
    band: f64,
    reach: Box3,
) -> Vec<(&'static str, f64)> {
    let bounds = surface.bounds();
    let hierarchy = surface.triangles.len() as f64 * HIERARCHY_BYTES_PER_TRIANGLE
        + surface.vertices.len() as f64 * 48.0;
    let overlap = |a: usize| (bounds.1[a].min(reach.1[a]) - bounds.0[a].max(reach.0[a])).max(0.0);
    let (table, samples) = SampledDistance::table_bytes(
        bounds,
        spacing,
        band,
        band + 4.0 * spacing,
        reach,
        overlap(0) * overlap(1),
    );
    let mut parts = vec![
        ("triangle hierarchy", hierarchy),
        ("distance lattice", table + samples),
    ];
    if role == Role::Die {
        let plan = ([reach.0[0], reach.0[1]], [reach.1[0], reach.1[1]]);
        parts.push(("face raster", Flange::raster_bytes(bounds, spacing, plan)));
    }
    parts
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
        Self::within(role, name, surface, spacing, band, &Limits::EVERYWHERE)
    }

    /// [`MeshTool::new`] with its lattice and face raster kept where the fabric can be
    /// (`limits.reach`), refused before anything is allocated when its tables would take more
    /// than `limits.budget_bytes` (see [`footprint`]).
    pub fn within(
        role: Role,
        name: &str,
        surface: &TriSurface,
        spacing: f64,
        band: f64,
        limits: &Limits,
    ) -> Result<MeshTool, PlacementError> {
        let bounds = surface.bounds();
        placed(role, bounds)?;
        let parts = footprint(role, surface, spacing, band, limits.reach);
        let total: f64 = parts.iter().map(|p| p.1).sum();
        if total > limits.budget_bytes || !total.is_finite() {
            let (part, part_bytes) = parts
                .iter()
                .fold(("", 0.0), |m, p| if p.1 > m.1 { *p } else { m });
            return Err(PlacementError::TooLarge {
                total,
                part,
                part_bytes,
                limit: limits.budget_bytes,
            });
        }
        let r = limits.reach;
        let flange = match role {
            Role::Punch => None,
            Role::Die => Some(
                Flange::within(surface, spacing, ([r.0[0], r.0[1]], [r.1[0], r.1[1]])).map_err(
                    |e| match e {
                        NoFlange::NoFace => PlacementError::NoFace,
                        NoFlange::OutsideReach => PlacementError::FaceNotUnderBlank { near: r },
                    },
                )?,
            ),
        };
        let distance =
            SampledDistance::within(surface, spacing, band, band + 4.0 * spacing, limits.reach);
        Ok(MeshTool {
            role,
            name: name.to_string(),
            triangles: surface.triangles.len(),
            distance,
            flange,
            bounds,
            vertices: surface.vertices.clone(),
            fingerprint: fingerprint(surface),
        })
    }

    /// A hash of the tool's surface (its vertices and triangles), stable across platforms:
    /// two files holding the same surface have the same.
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
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
