//! A closed triangle surface: the boundary of a rigid tool read from a mesh (STL). Triangles
//! wind counter-clockwise seen from outside the tool's material, so their right-hand normals
//! point out of it.
//!
//! [`TriSurface::from_soup`] welds the corners that coincide (a triangle soup, as STL stores
//! it, repeats every vertex) and [`TriSurface::check`] refuses what no tool can be: no
//! triangles, coordinates that are not numbers, a surface with holes (an edge with one
//! triangle), triangles facing both ways, a triangle with no area, an inside-out surface
//! (negative enclosed volume), a surface passing through itself ([`super::intersect`]) and
//! shells enclosing material twice ([`super::shells`]).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A multiply-rotate hash for integer keys (vertex keys and edges): the standard library's
/// SipHash guards against adversarial keys, which a surface's welding does not need, at
/// several times the cost over hundreds of thousands of keys.
#[derive(Default)]
pub(super) struct IntHasher(u64);

impl Hasher for IntHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_u32(&mut self, v: u32) {
        self.write_u64(v as u64);
    }
    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }
}

pub(super) type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<IntHasher>>;

/// Why a triangle surface cannot be a tool's boundary.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SurfaceError {
    #[error("it has no triangles")]
    Empty,
    #[error("triangle {triangle} has a coordinate that is not a finite number")]
    NotFinite { triangle: usize },
    #[error(
        "it is not closed (not watertight): {open_edges} edges belong to one triangle only, \
         e.g. the edge from {from:?} to {to:?} mm; a tool must enclose its material"
    )]
    Open {
        open_edges: usize,
        from: [f64; 3],
        to: [f64; 3],
    },
    #[error(
        "{edges} edges are shared by more than two triangles, e.g. the edge from {from:?} to \
         {to:?} mm (not a manifold surface)"
    )]
    NonManifold {
        edges: usize,
        from: [f64; 3],
        to: [f64; 3],
    },
    #[error(
        "its triangles do not face one way: {edges} edges are run the same way by both their \
         triangles, e.g. the edge from {from:?} to {to:?} mm; wind every triangle \
         counter-clockwise seen from outside"
    )]
    Inconsistent {
        edges: usize,
        from: [f64; 3],
        to: [f64; 3],
    },
    #[error(
        "it is inside out: its triangles' normals point into the material (enclosed volume \
         {volume_mm3:.4e} mm³ is negative); flip the triangles' winding (e.g. ParaView's \
         Reverse Sense, Blender's Flip Normals)"
    )]
    InsideOut { volume_mm3: f64 },
    #[error(
        "{dropped} of its {total} triangles lost a corner when corners within {quantum_mm:.3e} \
         mm of each other were joined (a billionth of its largest coordinate, {largest_mm:.3e} \
         mm): is a coordinate far from the others (a stray vertex), or are its triangles \
         smaller than that?"
    )]
    Collapsed {
        dropped: usize,
        total: usize,
        quantum_mm: f64,
        largest_mm: f64,
    },
    #[error("it encloses no volume ({volume_mm3:.3e} mm³): a flat or degenerate surface")]
    NoVolume { volume_mm3: f64 },
    #[error(
        "a triangle near {} mm has its three corners in a line (no area, so it faces no \
         way): repair the mesh (a zero-area sliver between two faces)",
        mm(at)
    )]
    Degenerate { at: [f64; 3] },
    #[error(
        "it passes through itself: two of its triangles cross near {} mm (two overlapping \
         solids in one file, or a surface folded through itself); a tool must enclose its \
         material once: unite the solids (a boolean union) or repair the mesh",
        mm(at)
    )]
    SelfIntersecting { at: [f64; 3] },
    #[error(
        "it encloses material twice: {} near {} mm lies {}; unite the solids (a boolean union) \
         or remove the inner one",
        if *solid { "a closed shell" } else { "a cavity (a shell facing inwards)" },
        mm(at),
        if *solid { "inside another solid" } else { "outside any solid" }
    )]
    Misnested { at: [f64; 3], solid: bool },
}

/// A point as a message shows it: `(1.250, -3.000, 0.000)`.
fn mm(p: &[f64; 3]) -> String {
    format!("({:.3}, {:.3}, {:.3})", p[0], p[1], p[2])
}

/// An indexed triangle surface, mm.
#[derive(Clone, Debug, PartialEq)]
pub struct TriSurface {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

impl TriSurface {
    /// Welds the corners of a triangle soup that lie within `1e-9` of the soup's size of each
    /// other (exactly equal corners, as STL writers repeat them, always weld) and drops the
    /// triangles that lose a corner to the weld (zero area). Non-finite coordinates are refused,
    /// and so is a soup that loses most of its triangles to the weld (a stray coordinate far
    /// from the others makes the weld's quantum larger than the triangles).
    pub fn from_soup(soup: &[[[f64; 3]; 3]]) -> Result<TriSurface, SurfaceError> {
        if soup.is_empty() {
            return Err(SurfaceError::Empty);
        }
        if let Some(t) = soup
            .iter()
            .position(|t| t.iter().flatten().any(|v| !v.is_finite()))
        {
            return Err(SurfaceError::NotFinite { triangle: t });
        }
        let size = soup
            .iter()
            .flatten()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(1e-300);
        let quantum = 1e-9 * size;
        let key = |p: &[f64; 3]| p.map(|v| (v / quantum).round() as i64);
        let mut index: FastMap<[i64; 3], u32> =
            FastMap::with_capacity_and_hasher(soup.len() / 2 + 8, Default::default());
        let mut vertices = Vec::with_capacity(soup.len() / 2 + 8);
        let mut triangles = Vec::with_capacity(soup.len());
        for tri in soup {
            let ids = tri.map(|p| {
                *index.entry(key(&p)).or_insert_with(|| {
                    vertices.push(p);
                    (vertices.len() - 1) as u32
                })
            });
            if ids[0] != ids[1] && ids[1] != ids[2] && ids[0] != ids[2] {
                triangles.push(ids);
            }
        }
        // A few slivers with repeated corners go; most of the triangles going is no weld.
        let dropped = soup.len() - triangles.len();
        if dropped > soup.len() / 2 {
            return Err(SurfaceError::Collapsed {
                dropped,
                total: soup.len(),
                quantum_mm: quantum,
                largest_mm: size,
            });
        }
        Ok(TriSurface {
            vertices,
            triangles,
        })
    }

    /// The three corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [[f64; 3]; 3] {
        self.triangles[t].map(|v| self.vertices[v as usize])
    }

    /// The enclosed volume by the divergence theorem, mm³: positive when the triangles face
    /// out.
    pub fn volume_mm3(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                let cross = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
            })
            .sum()
    }

    /// The corners of the surface's bounding box, mm.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in &self.vertices {
            for i in 0..3 {
                lo[i] = lo[i].min(v[i]);
                hi[i] = hi[i].max(v[i]);
            }
        }
        (lo, hi)
    }

    /// The surface moved by `offset`, mm.
    pub fn translated(&self, offset: [f64; 3]) -> TriSurface {
        TriSurface {
            vertices: self
                .vertices
                .iter()
                .map(|v| [v[0] + offset[0], v[1] + offset[1], v[2] + offset[2]])
                .collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// Each triangle as three corners (what STL stores).
    pub fn soup(&self) -> Vec<[[f64; 3]; 3]> {
        (0..self.triangles.len()).map(|t| self.corners(t)).collect()
    }
}

/// The 12 triangles of the axis-aligned box from `lo` to `hi`, facing out: the simplest closed
/// tool (tests build theirs from it).
pub fn box_soup(lo: [f64; 3], hi: [f64; 3]) -> Vec<[[f64; 3]; 3]> {
    let v = |i: usize| [0, 1, 2].map(|a| if (i >> a) & 1 == 0 { lo[a] } else { hi[a] });
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    quads
        .iter()
        .flat_map(|q| [[v(q[0]), v(q[1]), v(q[2])], [v(q[0]), v(q[2]), v(q[3])]])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's 12 triangles, facing out.
    fn cube() -> Vec<[[f64; 3]; 3]> {
        let v = |i: usize| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64];
        // Quads as corner indices, counter-clockwise seen from outside.
        let quads = [
            [0, 2, 3, 1], // z = 0
            [4, 5, 7, 6], // z = 1
            [0, 1, 5, 4], // y = 0
            [2, 6, 7, 3], // y = 1
            [0, 4, 6, 2], // x = 0
            [1, 3, 7, 5], // x = 1
        ];
        quads
            .iter()
            .flat_map(|q| [[v(q[0]), v(q[1]), v(q[2])], [v(q[0]), v(q[2]), v(q[3])]])
            .collect()
    }

    #[test]
    fn a_closed_cube_welds_and_encloses_its_volume() {
        let s = TriSurface::from_soup(&cube()).unwrap();
        assert_eq!(s.vertices.len(), 8);
        assert_eq!(s.triangles.len(), 12);
        assert!((s.check().unwrap() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn what_cannot_bound_a_tool_is_named() {
        assert_eq!(TriSurface::from_soup(&[]), Err(SurfaceError::Empty));
        let mut open = cube();
        open.pop();
        let e = TriSurface::from_soup(&open).unwrap().check().unwrap_err();
        assert!(matches!(e, SurfaceError::Open { open_edges: 3, .. }), "{e}");
        let inverted: Vec<_> = cube().iter().map(|t| [t[0], t[2], t[1]]).collect();
        let e = TriSurface::from_soup(&inverted)
            .unwrap()
            .check()
            .unwrap_err();
        assert!(matches!(e, SurfaceError::InsideOut { .. }), "{e}");
        let mut mixed = cube();
        mixed[0] = [mixed[0][0], mixed[0][2], mixed[0][1]];
        let e = TriSurface::from_soup(&mixed).unwrap().check().unwrap_err();
        assert!(matches!(e, SurfaceError::Inconsistent { .. }), "{e}");
        // One corner a light-year away: the weld's quantum swallows the cube.
        let mut stray = cube();
        stray[0][0] = [1e30, 0.0, 0.0];
        let e = TriSurface::from_soup(&stray).unwrap_err();
        assert!(
            matches!(
                e,
                SurfaceError::Collapsed {
                    dropped: 12,
                    total: 12,
                    ..
                }
            ),
            "{e}"
        );
        let mut nan = cube();
        nan[5][1][2] = f64::NAN;
        assert_eq!(
            TriSurface::from_soup(&nan),
            Err(SurfaceError::NotFinite { triangle: 5 })
        );
    }
}
