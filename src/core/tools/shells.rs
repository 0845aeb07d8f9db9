//! The closed shells of a surface and how they nest. A tool may be several closed surfaces
//! (two separate bumps, or a solid with a cavity: a shell facing inwards inside another), but
//! its material must be enclosed once: a shell facing outwards inside another's material (two
//! solids one inside the other) or a cavity in empty space is no tool.
//!
//! Each shell's winding number is taken at one of its vertices from the other shells (the sum
//! of their triangles' solid angles over 4π, Van Oosterom & Strackee 1983): 0 for a shell in
//! empty space, 1 for one in material. A shell enclosing material (positive volume) must lie
//! in empty space, a cavity (negative volume) in material. The point is on no other shell
//! (shells that touch are found as crossings first), so the sum is an integer to rounding.

use rayon::prelude::*;

use super::surface::TriSurface;

/// A shell that does not bound the material once, and one of its points, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Misnested {
    pub at: [f64; 3],
    /// Whether the shell encloses material (faces outwards) rather than a cavity.
    pub solid: bool,
}

/// The triangles of each connected shell (triangles joined by shared vertices).
fn shells(surface: &TriSurface) -> Vec<Vec<usize>> {
    let mut parent: Vec<u32> = (0..surface.vertices.len() as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let up = parent[parent[v as usize] as usize];
            parent[v as usize] = up;
            v = up;
        }
        v
    }
    for t in &surface.triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
    }
    let mut index = vec![u32::MAX; surface.vertices.len()];
    let mut out: Vec<Vec<usize>> = Vec::new();
    for (i, t) in surface.triangles.iter().enumerate() {
        let r = root(&mut parent, t[0]) as usize;
        if index[r] == u32::MAX {
            index[r] = out.len() as u32;
            out.push(Vec::new());
        }
        out[index[r] as usize].push(i);
    }
    out
}

/// The solid angle of triangle `[a, b, c]` seen from `x`, over 4π.
fn solid_angle_fraction(x: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> f64 {
    let r = [a, b, c].map(|p| [p[0] - x[0], p[1] - x[1], p[2] - x[2]]);
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let len = r.map(|u| dot(u, u).sqrt());
    let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
        - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
        + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    let den = len[0] * len[1] * len[2]
        + dot(r[0], r[1]) * len[2]
        + dot(r[0], r[2]) * len[1]
        + dot(r[1], r[2]) * len[0];
    2.0 * det.atan2(den) / (4.0 * std::f64::consts::PI)
}

/// The first shell that does not bound the material once (see the module's note), if any.
pub fn misnested_shell(surface: &TriSurface) -> Option<Misnested> {
    let shells = shells(surface);
    if shells.len() < 2 {
        return None;
    }
    let bounds: Vec<([f64; 3], [f64; 3])> = shells
        .iter()
        .map(|s| {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for p in s.iter().flat_map(|&t| surface.corners(t)) {
                for i in 0..3 {
                    lo[i] = lo[i].min(p[i]);
                    hi[i] = hi[i].max(p[i]);
                }
            }
            (lo, hi)
        })
        .collect();
    let volume = |s: &[usize]| -> f64 {
        s.iter()
            .map(|&t| {
                let [a, b, c] = surface.corners(t);
                let cross = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]
            })
            .sum()
    };
    (0..shells.len()).into_par_iter().find_map_first(|k| {
        let x = surface.vertices[surface.triangles[shells[k][0]][0] as usize];
        // A shell whose box does not hold the point adds nothing to its winding number.
        let winding: f64 = (0..shells.len())
            .filter(|&o| o != k && (0..3).all(|i| bounds[o].0[i] <= x[i] && x[i] <= bounds[o].1[i]))
            .map(|o| {
                shells[o]
                    .iter()
                    .map(|&t| solid_angle_fraction(x, surface.corners(t)))
                    .sum::<f64>()
            })
            .sum();
        let solid = volume(&shells[k]) > 0.0;
        let expected = if solid { 0.0 } else { 1.0 };
        ((winding - expected).abs() > 0.5).then_some(Misnested { at: x, solid })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cuboid(lo: [f64; 3], hi: [f64; 3], outward: bool) -> Vec<[[f64; 3]; 3]> {
        let soup = super::super::surface::box_soup(lo, hi).into_iter();
        soup.map(|t| if outward { t } else { [t[0], t[2], t[1]] })
            .collect()
    }

    fn of(parts: &[Vec<[[f64; 3]; 3]>]) -> Option<Misnested> {
        let soup: Vec<_> = parts.iter().flatten().copied().collect();
        misnested_shell(&TriSurface::from_soup(&soup).unwrap())
    }

    #[test]
    fn shells_bound_the_material_once() {
        let outer = cuboid([0.0; 3], [10.0; 3], true);
        // One shell; two apart; a solid with a cavity; an island in the cavity.
        assert_eq!(of(std::slice::from_ref(&outer)), None);
        assert_eq!(
            of(&[outer.clone(), cuboid([20.0; 3], [30.0; 3], true)]),
            None
        );
        let cavity = cuboid([2.0; 3], [8.0; 3], false);
        assert_eq!(of(&[outer.clone(), cavity.clone()]), None);
        let island = cuboid([4.0; 3], [6.0; 3], true);
        assert_eq!(of(&[outer.clone(), cavity, island]), None);
        // A solid inside a solid: the inner one is found.
        let inner = cuboid([2.0; 3], [8.0; 3], true);
        let m = of(&[outer.clone(), inner]).expect("nested solids");
        assert!(
            m.solid && m.at.iter().all(|&v| v == 2.0 || v == 8.0),
            "{m:?}"
        );
        // A cavity in empty space.
        let m = of(&[outer, cuboid([20.0; 3], [30.0; 3], false)]).expect("a stray cavity");
        assert!(!m.solid, "{m:?}");
    }
}
