//! The exact signed distance to a closed triangle surface: the nearest triangle through a
//! bounding-volume hierarchy (the `bvh` crate), the nearest point on it, and the sign from the
//! angle-weighted pseudonormal of the feature (face, edge or corner) that point lies on
//! (Bærentzen & Aanæs 2005), which is right for any closed, outward-facing surface.

use bvh::aabb::{Aabb, Bounded};
use bvh::bounding_hierarchy::{BHShape, BoundingHierarchy};
use bvh::bvh::Bvh;
use bvh::point_query::PointDistance;
use nalgebra::Point3;

use super::surface::TriSurface;

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn add_scaled(a: &mut V3, s: f64, b: V3) {
    for i in 0..3 {
        a[i] += s * b[i];
    }
}
fn unit(a: V3) -> V3 {
    let l = dot(a, a).sqrt();
    if l > 0.0 { a.map(|v| v / l) } else { a }
}

/// Where on a triangle its nearest point to a query lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Feature {
    Corner(usize),
    /// The edge from corner k to corner k + 1.
    Edge(usize),
    Face,
}

/// The point of triangle `[a, b, c]` nearest to `p`, and the feature it lies on (Ericson,
/// Real-Time Collision Detection, 5.1.5).
fn nearest_on_triangle(p: V3, [a, b, c]: [V3; 3]) -> (V3, Feature) {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Corner(0));
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Corner(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        let mut q = a;
        add_scaled(&mut q, v, ab);
        return (q, Feature::Edge(0));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Corner(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        let mut q = a;
        add_scaled(&mut q, w, ac);
        return (q, Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        let mut q = b;
        add_scaled(&mut q, w, sub(c, b));
        return (q, Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    let mut q = a;
    add_scaled(&mut q, v, ab);
    add_scaled(&mut q, w, ac);
    (q, Feature::Face)
}

/// A triangle as the hierarchy stores it.
struct Facet {
    corners: [V3; 3],
    index: usize,
    node: usize,
}

impl Bounded<f64, 3> for Facet {
    fn aabb(&self) -> Aabb<f64, 3> {
        let [a, b, c] = self.corners;
        let lo = [0, 1, 2].map(|i| a[i].min(b[i]).min(c[i]));
        let hi = [0, 1, 2].map(|i| a[i].max(b[i]).max(c[i]));
        Aabb::with_bounds(Point3::from(lo), Point3::from(hi))
    }
}

impl BHShape<f64, 3> for Facet {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node = index;
    }
    fn bh_node_index(&self) -> usize {
        self.node
    }
}

impl PointDistance<f64, 3> for Facet {
    fn distance_squared(&self, q: Point3<f64>) -> f64 {
        let p = [q.x, q.y, q.z];
        let (x, _) = nearest_on_triangle(p, self.corners);
        let d = sub(p, x);
        dot(d, d)
    }
}

/// The exact signed distance to a closed surface (negative inside), its nearest point and
/// the outward direction.
pub struct ExactDistance {
    facets: Vec<Facet>,
    bvh: Bvh<f64, 3>,
    triangles: Vec<[u32; 3]>,
    /// Unit normal of each triangle.
    face_normal: Vec<V3>,
    /// Pseudonormal of each triangle's edge k → k + 1 (the sum of its two faces' normals).
    edge_normal: Vec<[V3; 3]>,
    /// Angle-weighted pseudonormal of each vertex.
    vertex_normal: Vec<V3>,
}

/// One answer of [`ExactDistance::query`].
#[derive(Clone, Copy, Debug)]
pub struct Nearest {
    /// Signed distance, mm (negative inside the material).
    pub d: f64,
    /// The nearest surface point, mm.
    pub point: V3,
    /// The outward unit direction: from the nearest point to the query (its reverse inside),
    /// or the feature's pseudonormal on the surface.
    pub n: V3,
}

impl ExactDistance {
    /// The hierarchy and pseudonormals of a checked surface ([`TriSurface::check`]).
    pub fn new(surface: &TriSurface) -> ExactDistance {
        let triangles = surface.triangles.clone();
        let mut facets: Vec<Facet> = (0..triangles.len())
            .map(|t| Facet {
                corners: surface.corners(t),
                index: t,
                node: 0,
            })
            .collect();
        let bvh = Bvh::build_par(&mut facets);
        let face_normal: Vec<V3> = facets
            .iter()
            .map(|f| {
                let [a, b, c] = f.corners;
                unit(cross(sub(b, a), sub(c, a)))
            })
            .collect();
        let mut vertex_normal = vec![[0.0; 3]; surface.vertices.len()];
        // Each edge as (low vertex, high vertex, triangle, side), sorted: the two triangles of
        // an edge of a closed surface lie next to each other.
        let mut edges: Vec<(u32, u32, u32, u8)> = Vec::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            let corners = facets[t].corners;
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                edges.push((a.min(b), a.max(b), t as u32, k as u8));
                let (u, w) = (
                    unit(sub(corners[(k + 1) % 3], corners[k])),
                    unit(sub(corners[(k + 2) % 3], corners[k])),
                );
                let angle = dot(u, w).clamp(-1.0, 1.0).acos();
                add_scaled(&mut vertex_normal[a as usize], angle, face_normal[t]);
            }
        }
        edges.sort_unstable();
        let mut edge_normal = vec![[[0.0; 3]; 3]; triangles.len()];
        for group in edges.chunk_by(|x, y| x.0 == y.0 && x.1 == y.1) {
            let mut sum = [0.0; 3];
            for e in group {
                add_scaled(&mut sum, 1.0, face_normal[e.2 as usize]);
            }
            for e in group {
                edge_normal[e.2 as usize][e.3 as usize] = sum;
            }
        }
        ExactDistance {
            facets,
            bvh,
            triangles,
            face_normal,
            edge_normal,
            vertex_normal,
        }
    }

    /// The plane of the surface within the box `[lo, hi]` when every triangle reaching into
    /// it lies in one plane (within 1e-5 mm, as STL's single precision allows): its outward
    /// unit normal `n` and offset `c`, the surface there being `n·x = c`.
    pub fn plane_within(&self, lo: V3, hi: V3) -> Option<(V3, f64)> {
        let query = Aabb::with_bounds(Point3::from(lo), Point3::from(hi));
        let mut plane: Option<(V3, f64)> = None;
        for f in self.bvh.traverse_iterator(&query, &self.facets) {
            let n = self.face_normal[f.index];
            let (n0, c) = *plane.get_or_insert((n, dot(n, f.corners[0])));
            if dot(n, n0) < 1.0 - 1e-8 || f.corners.iter().any(|v| (dot(n0, *v) - c).abs() > 1e-5) {
                return None;
            }
        }
        plane
    }

    /// The unit angle-weighted normal at vertex `v`.
    pub fn vertex_normal(&self, v: usize) -> V3 {
        unit(self.vertex_normal[v])
    }

    /// The triangles, as vertex indices.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The signed distance at `p`, its nearest point and outward direction.
    pub fn query(&self, p: V3) -> Nearest {
        let Some((facet, _)) = self.bvh.nearest_to(Point3::from(p), &self.facets) else {
            return Nearest {
                d: f64::INFINITY,
                point: p,
                n: [0.0, 0.0, 1.0],
            };
        };
        let t = facet.index;
        let (x, feature) = nearest_on_triangle(p, facet.corners);
        let pseudo = match feature {
            Feature::Face => self.face_normal[t],
            Feature::Edge(k) => self.edge_normal[t][k],
            Feature::Corner(k) => self.vertex_normal[self.triangles[t][k] as usize],
        };
        let v = sub(p, x);
        let dist = dot(v, v).sqrt();
        let outside = dot(v, pseudo) >= 0.0;
        let n = if dist > 1e-12 {
            let s = if outside { 1.0 } else { -1.0 };
            v.map(|c| s * c / dist)
        } else {
            unit(pseudo)
        };
        Nearest {
            d: if outside { dist } else { -dist },
            point: x,
            n,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearest_point_of_a_triangle_by_region() {
        let tri = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        let cases = [
            ([0.5, 0.5, 1.0], [0.5, 0.5, 0.0], Feature::Face),
            ([-1.0, -1.0, 0.0], [0.0, 0.0, 0.0], Feature::Corner(0)),
            ([3.0, -0.5, 0.0], [2.0, 0.0, 0.0], Feature::Corner(1)),
            ([1.0, -1.0, 0.5], [1.0, 0.0, 0.0], Feature::Edge(0)),
            ([2.0, 2.0, 0.0], [1.0, 1.0, 0.0], Feature::Edge(1)),
            ([-1.0, 1.0, 0.0], [0.0, 1.0, 0.0], Feature::Edge(2)),
        ];
        for (p, x, f) in cases {
            let (q, g) = nearest_on_triangle(p, tri);
            assert_eq!(g, f, "{p:?}");
            assert!(sub(q, x).iter().all(|v| v.abs() < 1e-12), "{p:?}: {q:?}");
        }
    }
}
