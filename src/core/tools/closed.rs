//! Whether a triangle surface can bound a tool: closed, manifold, consistently oriented, with
//! no degenerate triangle, a volume facing out, no self-intersection and no shell nested the
//! wrong way (the checks themselves in [`super::intersect`] and [`super::shells`]).

use super::intersect;
use super::shells;
use super::surface::{FastMap, SurfaceError, TriSurface};

impl TriSurface {
    /// Refuses a surface that cannot bound a tool (see the module's note). Returns the enclosed
    /// volume, mm³.
    pub fn check(&self) -> Result<f64, SurfaceError> {
        if self.triangles.is_empty() {
            return Err(SurfaceError::Empty);
        }
        // Each undirected edge: (uses a→b, uses b→a) with a < b.
        let mut edges: FastMap<(u32, u32), (u32, u32)> =
            FastMap::with_capacity_and_hasher(3 * self.triangles.len() / 2 + 8, Default::default());
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let e = edges.entry((a.min(b), a.max(b))).or_default();
                if a < b {
                    e.0 += 1;
                } else {
                    e.1 += 1;
                }
            }
        }
        let at = |e: &(u32, u32)| (self.vertices[e.0 as usize], self.vertices[e.1 as usize]);
        let find = |bad: &dyn Fn(&(u32, u32)) -> bool| {
            let mut list: Vec<&(u32, u32)> = edges
                .iter()
                .filter(|(_, uses)| bad(uses))
                .map(|(e, _)| e)
                .collect();
            list.sort();
            (list.len(), list.first().map(|e| at(e)))
        };
        if let (n, Some((from, to))) = find(&|u| u.0 + u.1 == 1) {
            return Err(SurfaceError::Open {
                open_edges: n,
                from,
                to,
            });
        }
        if let (n, Some((from, to))) = find(&|u| u.0 + u.1 > 2) {
            return Err(SurfaceError::NonManifold { edges: n, from, to });
        }
        if let (n, Some((from, to))) = find(&|u| u.0 != 1 || u.1 != 1) {
            return Err(SurfaceError::Inconsistent { edges: n, from, to });
        }
        if let Some((_, at)) = intersect::degenerate_triangle(self) {
            return Err(SurfaceError::Degenerate { at });
        }
        let volume = self.volume_mm3();
        let (lo, hi) = self.bounds();
        let box_volume: f64 = (0..3).map(|i| (hi[i] - lo[i]).max(0.0)).product();
        if volume.abs() <= 1e-9 * box_volume.max(1e-300) || box_volume == 0.0 {
            return Err(SurfaceError::NoVolume { volume_mm3: volume });
        }
        if volume < 0.0 {
            return Err(SurfaceError::InsideOut { volume_mm3: volume });
        }
        if let Some(c) = intersect::self_intersection(self) {
            return Err(SurfaceError::SelfIntersecting { at: c.at });
        }
        if let Some(m) = shells::misnested_shell(self) {
            return Err(SurfaceError::Misnested {
                at: m.at,
                solid: m.solid,
            });
        }
        Ok(volume)
    }
}
