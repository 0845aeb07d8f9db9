//! Whether a closed triangle surface passes through itself: two overlapping solids written in
//! one file, or a surface folded through itself, bound no single material (inside and outside
//! are not defined), and a tool's signed distance is wrong around them.
//!
//! The test is exact: the vertices are snapped to the welding quantum of
//! [`TriSurface::from_soup`] (1e-9 of the surface's size, so distinct welded vertices stay
//! distinct) and every predicate (which side of a plane or a line a point lies) is computed in
//! integers, so that triangles that merely share an edge or a corner are never taken for
//! crossing ones, whatever their shape. Two triangles are tested when their bounding boxes
//! meet (found through a bounding-volume hierarchy): with no corner in common, any contact is
//! a crossing (touching included); with one corner in common, any contact besides that corner;
//! with an edge in common, only a fold flat onto each other.

use bvh::aabb::{Aabb, Bounded};
use bvh::bounding_hierarchy::{BHShape, BoundingHierarchy};
use bvh::bvh::Bvh;
use nalgebra::Point3;
use rayon::prelude::*;

use super::surface::TriSurface;

type P3 = [i64; 3];

/// Two triangles of a surface that meet where they should not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The two triangles (indices into the surface's triangles).
    pub triangles: [usize; 2],
    /// A point where they meet, mm.
    pub at: [f64; 3],
}

/// The surface's vertices on the integer grid of the welding quantum.
struct Snapped {
    points: Vec<P3>,
    quantum: f64,
}

impl Snapped {
    fn of(surface: &TriSurface) -> Snapped {
        let size = surface
            .vertices
            .iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(1e-300);
        let quantum = 1e-9 * size;
        let points = surface
            .vertices
            .iter()
            .map(|p| p.map(|v| (v / quantum).round() as i64))
            .collect();
        Snapped { points, quantum }
    }

    fn mm(&self, p: [f64; 3]) -> [f64; 3] {
        p.map(|v| v * self.quantum)
    }
}

fn sub(a: P3, b: P3) -> [i128; 3] {
    [0, 1, 2].map(|i| (a[i] - b[i]) as i128)
}

fn cross(u: [i128; 3], v: [i128; 3]) -> [i128; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// The sign of the signed volume of the tetrahedron `a b c d` (positive when `d` lies on the
/// side of the plane `a b c` that its counter-clockwise normal points to), exact: in floating
/// point when its rounding error bound (7ε of the terms' magnitudes: the differences of
/// coordinates below 2³¹ are exact) cannot change it, else in 128-bit integers.
fn orient3d(a: P3, b: P3, c: P3, d: P3) -> i128 {
    let f = |p: P3, q: P3| [0, 1, 2].map(|i| (p[i] - q[i]) as f64);
    let (u, v, w) = (f(b, a), f(c, a), f(d, a));
    let t = [
        u[0] * (v[1] * w[2] - v[2] * w[1]),
        u[1] * (v[2] * w[0] - v[0] * w[2]),
        u[2] * (v[0] * w[1] - v[1] * w[0]),
    ];
    let magnitude = u[0].abs() * (v[1] * w[2]).abs().max((v[2] * w[1]).abs())
        + u[1].abs() * (v[2] * w[0]).abs().max((v[0] * w[2]).abs())
        + u[2].abs() * (v[0] * w[1]).abs().max((v[1] * w[0]).abs());
    let det = t[0] + t[1] + t[2];
    if det.abs() > 1e-14 * magnitude {
        return if det > 0.0 { 1 } else { -1 };
    }
    let n = cross(sub(b, a), sub(c, a));
    let w = sub(d, a);
    (n[0] * w[0] + n[1] * w[1] + n[2] * w[2]).signum()
}

/// An approximation of six times the signed volume of `a b c d`, for a crossing's place.
fn volume6(a: P3, b: P3, c: P3, d: P3) -> f64 {
    let f = |p: P3, q: P3| [0, 1, 2].map(|i| (p[i] - q[i]) as f64);
    let (u, v, w) = (f(b, a), f(c, a), f(d, a));
    u[0] * (v[1] * w[2] - v[2] * w[1])
        + u[1] * (v[2] * w[0] - v[0] * w[2])
        + u[2] * (v[0] * w[1] - v[1] * w[0])
}

/// The triangle's doubled area vector, exact (zero when its corners lie in a line).
pub(super) fn area_vector(a: P3, b: P3, c: P3) -> [i128; 3] {
    cross(sub(b, a), sub(c, a))
}

/// The sign of the orientation of `c` from the line `a b` in the plane that drops `axis`,
/// exact (in floating point when its error bound allows, else in integers).
fn orient2d(a: P3, b: P3, c: P3, axis: usize) -> i128 {
    let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
    let (ux, uy) = ((b[i] - a[i]) as f64, (b[j] - a[j]) as f64);
    let (vx, vy) = ((c[i] - a[i]) as f64, (c[j] - a[j]) as f64);
    let (l, r) = (ux * vy, uy * vx);
    if (l - r).abs() > 1e-15 * (l.abs() + r.abs()) {
        return if l > r { 1 } else { -1 };
    }
    let (ux, uy) = ((b[i] - a[i]) as i128, (b[j] - a[j]) as i128);
    let (vx, vy) = ((c[i] - a[i]) as i128, (c[j] - a[j]) as i128);
    (ux * vy - uy * vx).signum()
}

/// The axis along which the triangle's normal is largest (the plane dropping it shows the
/// triangle undistorted enough: its projection keeps every orientation's sign).
fn dominant_axis(n: [i128; 3]) -> usize {
    let a = n.map(|v| v.unsigned_abs());
    if a[0] >= a[1] && a[0] >= a[2] {
        0
    } else if a[1] >= a[2] {
        1
    } else {
        2
    }
}

fn same_sign_or_zero(s: [i128; 3]) -> bool {
    s.iter().all(|&v| v >= 0) || s.iter().all(|&v| v <= 0)
}

/// Whether `p` lies in the closed coplanar triangle `t`, in the plane dropping `axis`.
fn in_triangle_2d(p: P3, t: [P3; 3], axis: usize) -> bool {
    same_sign_or_zero([0, 1, 2].map(|k| orient2d(t[k], t[(k + 1) % 3], p, axis)))
}

/// Whether the closed coplanar segments `p q` and `a b` meet, in the plane dropping `axis`.
fn segments_meet_2d(p: P3, q: P3, a: P3, b: P3, axis: usize) -> bool {
    let (d1, d2) = (orient2d(a, b, p, axis), orient2d(a, b, q, axis));
    let (d3, d4) = (orient2d(p, q, a, axis), orient2d(p, q, b, axis));
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return true;
    }
    // Collinear touching: an end of one on the other.
    let on = |s: P3, e: P3, x: P3, d: i128| {
        d == 0 && (0..3).all(|i| s[i].min(e[i]) <= x[i] && x[i] <= s[i].max(e[i]))
    };
    on(a, b, p, d1) || on(a, b, q, d2) || on(p, q, a, d3) || on(p, q, b, d4)
}

/// Whether two closed triangles in one plane meet: no edge of either has the other wholly on
/// its outer side (the separating axis theorem), in the plane dropping `axis`.
fn coplanar_meet(t: [P3; 3], u: [P3; 3], axis: usize) -> bool {
    let separates = |x: [P3; 3], y: [P3; 3]| {
        let o = orient2d(x[0], x[1], x[2], axis);
        (0..3).any(|k| {
            y.iter()
                .all(|&p| orient2d(x[k], x[(k + 1) % 3], p, axis) * o < 0)
        })
    };
    !separates(t, u) && !separates(u, t)
}

/// Whether coplanar triangles `v a b` and `v c d`, which share the corner `v` only, meet
/// elsewhere: whether their angles at `v` overlap or touch along a ray (each triangle is its
/// angle near `v`, and lies within it).
fn wedges_meet(v: P3, [a, b]: [P3; 2], [c, d]: [P3; 2], axis: usize) -> bool {
    let inside = |p: P3, q: P3, x: P3| {
        let o = orient2d(v, p, q, axis);
        orient2d(v, p, x, axis) * o >= 0 && orient2d(v, x, q, axis) * o >= 0
    };
    inside(a, b, c) || inside(a, b, d) || inside(c, d, a) || inside(c, d, b)
}

/// Where the closed segment `p q` meets the closed triangle `t`, if it does (a point of the
/// contact, in quantum units).
fn segment_meets_triangle(p: P3, q: P3, t: [P3; 3]) -> Option<[f64; 3]> {
    let [a, b, c] = t;
    let (sp, sq) = (orient3d(a, b, c, p), orient3d(a, b, c, q));
    if sp * sq > 0 {
        return None;
    }
    let f = |x: P3| x.map(|v| v as f64);
    if sp == 0 && sq == 0 {
        let axis = dominant_axis(area_vector(a, b, c));
        for x in [p, q] {
            if in_triangle_2d(x, t, axis) {
                return Some(f(x));
            }
        }
        let crosses = (0..3).any(|k| segments_meet_2d(p, q, t[k], t[(k + 1) % 3], axis));
        // The point reported: the segment's middle (near enough to find the place).
        return crosses.then(|| [0, 1, 2].map(|i| 0.5 * (p[i] as f64 + q[i] as f64)));
    }
    let s = [
        orient3d(p, q, a, b),
        orient3d(p, q, b, c),
        orient3d(p, q, c, a),
    ];
    if !same_sign_or_zero(s) {
        return None;
    }
    let (vp, vq) = (volume6(a, b, c, p), volume6(a, b, c, q));
    let w = if vp == vq { 0.5 } else { vp / (vp - vq) }.clamp(0.0, 1.0);
    Some([0, 1, 2].map(|i| p[i] as f64 + w * (q[i] - p[i]) as f64))
}

fn centroid(t: [P3; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| (t[0][i] as f64 + t[1][i] as f64 + t[2][i] as f64) / 3.0)
}

/// Triangles `pt` and `pu` with no corner in common: whether they meet, and where.
fn apart_pair_meets(pt: [P3; 3], pu: [P3; 3]) -> Option<[f64; 3]> {
    let side = |x: [P3; 3], y: [P3; 3]| y.map(|v| orient3d(x[0], x[1], x[2], v));
    let (su, st) = (side(pt, pu), side(pu, pt));
    let strictly_one_side = |o: [i128; 3]| o.iter().all(|&v| v > 0) || o.iter().all(|&v| v < 0);
    if strictly_one_side(su) || strictly_one_side(st) {
        return None;
    }
    if su == [0; 3] {
        let axis = dominant_axis(area_vector(pt[0], pt[1], pt[2]));
        return coplanar_meet(pt, pu, axis).then(|| {
            let (a, b) = (centroid(pt), centroid(pu));
            [0, 1, 2].map(|i| 0.5 * (a[i] + b[i]))
        });
    }
    let edges = |x: [P3; 3], y: [P3; 3]| {
        (0..3).find_map(|k| segment_meets_triangle(x[k], x[(k + 1) % 3], y))
    };
    edges(pt, pu).or_else(|| edges(pu, pt))
}

/// Triangles `v a b` and `v c d` sharing the corner `v` only: whether they meet elsewhere.
fn corner_pair_meets(v: P3, ab: [P3; 2], cd: [P3; 2]) -> Option<[f64; 3]> {
    let (t, u) = ([v, ab[0], ab[1]], [v, cd[0], cd[1]]);
    if orient3d(v, cd[0], cd[1], ab[0]) == 0 && orient3d(v, cd[0], cd[1], ab[1]) == 0 {
        let axis = dominant_axis(area_vector(v, ab[0], ab[1]));
        return wedges_meet(v, ab, cd, axis).then(|| {
            let (a, b) = (centroid(t), centroid(u));
            [0, 1, 2].map(|i| 0.5 * (a[i] + b[i]))
        });
    }
    // The intersection of the two is a segment from `v`: beyond `v` it reaches the edge
    // facing `v` of one of them.
    segment_meets_triangle(ab[0], ab[1], u).or_else(|| segment_meets_triangle(cd[0], cd[1], t))
}

/// Triangles `v w a` and `w v c` sharing the edge `v w`: whether they are folded flat onto
/// each other (coplanar, `a` and `c` on the same side of the edge).
fn edge_pair_meets(v: P3, w: P3, a: P3, c: P3) -> Option<[f64; 3]> {
    if orient3d(v, w, a, c) != 0 {
        return None;
    }
    let axis = dominant_axis(area_vector(v, w, a));
    (orient2d(v, w, a, axis) * orient2d(v, w, c, axis) > 0).then(|| centroid([v, a, c]))
}

/// Whether triangles `t` and `u` (vertex indices) meet where they should not, and where (in
/// quantum units).
fn pair_meets(s: &Snapped, t: [u32; 3], u: [u32; 3]) -> Option<[f64; 3]> {
    let mut shared = [(0, 0); 3];
    let mut n = 0;
    for (i, a) in t.iter().enumerate() {
        if let Some(j) = u.iter().position(|b| b == a) {
            shared[n] = (i, j);
            n += 1;
        }
    }
    let pt = t.map(|v| s.points[v as usize]);
    let pu = u.map(|v| s.points[v as usize]);
    let rest = |x: [P3; 3], k: usize| [x[(k + 1) % 3], x[(k + 2) % 3]];
    match n {
        0 => apart_pair_meets(pt, pu),
        1 => {
            let (i, j) = shared[0];
            corner_pair_meets(pt[i], rest(pt, i), rest(pu, j))
        }
        2 => {
            let third = |x: [u32; 3], y: [u32; 3]| (0..3).find(|&k| !y.contains(&x[k]));
            let (a, c) = (third(t, u)?, third(u, t)?);
            edge_pair_meets(pt[shared[0].0], pt[shared[1].0], pt[a], pu[c])
        }
        _ => None,
    }
}

/// A triangle's bounding box, for the hierarchy.
struct Boxed {
    lo: [f64; 3],
    hi: [f64; 3],
    index: usize,
    node: usize,
}

impl Bounded<f64, 3> for Boxed {
    fn aabb(&self) -> Aabb<f64, 3> {
        Aabb::with_bounds(Point3::from(self.lo), Point3::from(self.hi))
    }
}

impl BHShape<f64, 3> for Boxed {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node = index;
    }
    fn bh_node_index(&self) -> usize {
        self.node
    }
}

/// The first pair of triangles (in the surface's order) that meet where they should not: not
/// along the edge or at the corner they share. `None` for a surface that does not pass
/// through itself. Its triangles must have area ([`degenerate_triangle`] finds none).
pub fn self_intersection(surface: &TriSurface) -> Option<Crossing> {
    let s = Snapped::of(surface);
    // Boxes on the snapped grid, grown by one quantum (the snapping moves a corner by half).
    let mut boxes: Vec<Boxed> = surface
        .triangles
        .iter()
        .enumerate()
        .map(|(index, t)| {
            let p = t.map(|v| s.points[v as usize]);
            let lo = [0, 1, 2].map(|i| p[0][i].min(p[1][i]).min(p[2][i]) as f64 - 1.0);
            let hi = [0, 1, 2].map(|i| p[0][i].max(p[1][i]).max(p[2][i]) as f64 + 1.0);
            Boxed {
                lo,
                hi,
                index,
                node: 0,
            }
        })
        .collect();
    if boxes.is_empty() {
        return None;
    }
    let bvh = Bvh::build_par(&mut boxes);
    let boxes = &boxes;
    (0..surface.triangles.len())
        .into_par_iter()
        .find_map_first(|i| {
            let query = boxes[i].aabb();
            let t = surface.triangles[i];
            let mut hits: Vec<usize> = bvh
                .traverse_iterator(&query, boxes)
                .map(|b| b.index)
                .filter(|&j| j > i)
                .collect();
            hits.sort_unstable();
            hits.into_iter().find_map(|j| {
                pair_meets(&s, t, surface.triangles[j]).map(|at| Crossing {
                    triangles: [i, j],
                    at: s.mm(at),
                })
            })
        })
}

/// The first triangle whose corners lie in a line (no area, so no side and no normal), on the
/// snapped grid of [`self_intersection`]; its index and its middle, mm.
pub fn degenerate_triangle(surface: &TriSurface) -> Option<(usize, [f64; 3])> {
    let s = Snapped::of(surface);
    surface.triangles.iter().enumerate().find_map(|(i, t)| {
        let p = t.map(|v| s.points[v as usize]);
        (area_vector(p[0], p[1], p[2]) == [0; 3]).then(|| {
            let c = surface.corners(i);
            (i, [0, 1, 2].map(|k| (c[0][k] + c[1][k] + c[2][k]) / 3.0))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cuboid(lo: [f64; 3], hi: [f64; 3]) -> Vec<[[f64; 3]; 3]> {
        super::super::surface::box_soup(lo, hi)
    }

    fn surface(soup: &[[[f64; 3]; 3]]) -> TriSurface {
        TriSurface::from_soup(soup).unwrap()
    }

    #[test]
    fn a_box_does_not_cross_itself_and_two_overlapping_boxes_do() {
        let one = cuboid([0.0; 3], [10.0; 3]);
        assert_eq!(self_intersection(&surface(&one)), None);
        // Two boxes sharing their bottom plane, overlapping in [5, 10]² (the walls' diagonals
        // cross exactly on each other: only exact predicates see it).
        let mut two = one.clone();
        two.extend(cuboid([5.0, 5.0, 0.0], [15.0, 15.0, 10.0]));
        let c = self_intersection(&surface(&two)).expect("the boxes overlap");
        assert!(
            (0..3).all(|i| c.at[i] >= -1e-9 && c.at[i] <= 15.0 + 1e-9),
            "{c:?}"
        );
        // Apart, they do not (two closed solids in one file; not crossing each other).
        let mut apart = one.clone();
        apart.extend(cuboid([20.0; 3], [30.0; 3]));
        assert_eq!(self_intersection(&surface(&apart)), None);
        // One inside the other: no face crosses a face (the shells' nesting is checked apart,
        // by `shells`).
        let mut nested = one.clone();
        nested.extend(cuboid([2.0; 3], [8.0; 3]));
        assert_eq!(self_intersection(&surface(&nested)), None);
    }

    #[test]
    fn a_corner_pushed_through_the_opposite_face_is_found() {
        // A cube whose top corner (10, 10, 10) is pushed down through its bottom face: the
        // surface stays closed and consistently wound, but its triangles now cross the bottom.
        let pushed: Vec<_> = cuboid([0.0; 3], [10.0; 3])
            .into_iter()
            .map(|t| t.map(|p| if p == [10.0; 3] { [4.0, 4.0, -5.0] } else { p }))
            .collect();
        let c = self_intersection(&surface(&pushed)).expect("the surface is folded through");
        // The crossing is on the bottom face, z = 0, within the cube's plan.
        assert!(c.at[2].abs() < 1e-6, "{c:?}");
        assert!(
            (0..2).all(|i| c.at[i] > -1e-6 && c.at[i] < 10.0 + 1e-6),
            "{c:?}"
        );
        // A fold: a square's two triangles folded flat onto each other.
        let fold = vec![
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.5, 0.5, 0.0]],
        ];
        let s = surface(&fold);
        assert!(pair_meets(&Snapped::of(&s), s.triangles[0], s.triangles[1]).is_some());
    }

    #[test]
    fn neighbours_in_a_flat_fan_do_not_meet() {
        // Six triangles around a centre in a plane: corner-sharing and edge-sharing pairs.
        let ring: Vec<[f64; 3]> = (0..6)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 6.0;
                [t.cos(), t.sin(), 0.0]
            })
            .collect();
        let soup: Vec<_> = (0..6)
            .map(|k| [[0.0, 0.0, 0.0], ring[k], ring[(k + 1) % 6]])
            .collect();
        let s = surface(&soup);
        let snapped = Snapped::of(&s);
        for i in 0..6 {
            for j in i + 1..6 {
                assert_eq!(pair_meets(&snapped, s.triangles[i], s.triangles[j]), None);
            }
        }
        // A corner of one fan triangle moved over its non-neighbour: they now overlap.
        let mut bent = soup.clone();
        bent[0][2] = [-0.6, 0.5, 0.0];
        let s = surface(&bent);
        let snapped = Snapped::of(&s);
        assert!(pair_meets(&snapped, s.triangles[0], s.triangles[2]).is_some());
    }

    #[test]
    fn collinear_corners_are_degenerate() {
        let soup = vec![
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [3.0, 3.0, 3.0]],
        ];
        let s = surface(&soup);
        assert_eq!(degenerate_triangle(&s).map(|d| d.0), Some(1));
    }
}
