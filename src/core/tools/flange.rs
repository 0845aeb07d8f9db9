//! A mesh die's flange: where its top face lies in the blank's plane z = 0, in plan, as a
//! smooth signed distance (positive on the face, negative over the opening) that the blank
//! holder weighs its pressure with, as it does with `d_open − rm` of an analytic die (the plan
//! distance from where the die's entry radius meets its face).
//!
//! The face is every triangle within `FACE_TOL_MM` of z = 0 facing up (within 1°). It is
//! rasterised on a plan grid, its exact Euclidean distance transform (Felzenszwalb &
//! Huttenlocher) gives the signed distance to its edge at the cells' centres, and bicubic
//! Catmull-Rom interpolation makes that C1.
//!
//! The raster covers the die's plan, but only where the blank can be
//! ([`Flange::within`]): a die plate far wider than the blank is not rasterised where no
//! fabric goes (cells are counted from the full raster's corner, so clipping moves none).

use super::surface::TriSurface;

/// A plan box, mm: its lowest and highest corners.
pub type Box2 = ([f64; 2], [f64; 2]);

/// Why a die has no flange where the blank is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoFlange {
    /// No triangle lies in z = 0 facing up.
    NoFace,
    /// Its face lies wholly outside the plan box given.
    OutsideReach,
}

/// The bytes the raster and its distance transforms take per cell.
const BYTES_PER_CELL: f64 = 41.0;

/// The cells of the full raster kept along each axis: the first one and how many (as `f64`,
/// so that a raster too large to allocate is measured without overflow).
fn cells(die_bounds: ([f64; 3], [f64; 3]), spacing: f64, reach: Box2) -> ([f64; 2], [[f64; 2]; 2]) {
    let (lo, hi) = die_bounds;
    let origin = [lo[0] - 2.0 * spacing, lo[1] - 2.0 * spacing];
    let full = [0, 1].map(|a| ((hi[a] - lo[a]) / spacing).ceil() + 5.0);
    let kept = [0, 1].map(|a| {
        let from = (((reach.0[a] - origin[a]) / spacing).floor() - 2.0).clamp(0.0, full[a]);
        let to = (((reach.1[a] - origin[a]) / spacing).ceil() + 2.0).clamp(0.0, full[a] - 1.0);
        [from, (to - from + 1.0).max(0.0)]
    });
    (origin, kept)
}

/// How far from z = 0 a face triangle's corners may lie, mm.
pub const FACE_TOL_MM: f64 = 0.01;

/// The flange field of a die.
#[derive(Clone, Debug)]
pub struct Flange {
    /// The full raster's corner (the cells kept start `first` cells further).
    origin: [f64; 2],
    first: [usize; 2],
    spacing: f64,
    dims: [usize; 2],
    /// Signed distance to the face's edge at each cell centre (row-major in x), mm.
    values: Vec<f64>,
    /// Area of the face, mm².
    pub face_area_mm2: f64,
}

/// Squared distances to the nearest zero of `f` (0 or ∞ per cell) along a line, in cells².
fn edt_line(f: &[f64], out: &mut [f64]) {
    let n = f.len();
    let mut v = vec![0usize; n];
    let mut z = vec![0.0f64; n + 1];
    let mut k = 0usize;
    let first = f.iter().position(|x| x.is_finite());
    let Some(first) = first else {
        out.iter_mut().for_each(|o| *o = f64::INFINITY);
        return;
    };
    v[0] = first;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in first + 1..n {
        if !f[q].is_finite() {
            continue;
        }
        loop {
            let p = v[k];
            let s = ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q - p) as f64);
            if s <= z[k] && k > 0 {
                k -= 1;
                continue;
            }
            if s <= z[k] {
                // k == 0 and the new parabola is lower everywhere.
                v[0] = q;
                z[1] = f64::INFINITY;
                break;
            }
            k += 1;
            v[k] = q;
            z[k] = s;
            z[k + 1] = f64::INFINITY;
            break;
        }
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *o = (q as f64 - p as f64).powi(2) + f[p];
    }
}

/// The squared distance (cells²) of each cell to the nearest cell where `zero` holds.
fn edt(dims: [usize; 2], zero: &dyn Fn(usize) -> bool) -> Vec<f64> {
    let [nx, ny] = dims;
    let mut g: Vec<f64> = (0..nx * ny)
        .map(|i| if zero(i) { 0.0 } else { f64::INFINITY })
        .collect();
    let mut col = vec![0.0; ny];
    let mut out = vec![0.0; ny.max(nx)];
    for x in 0..nx {
        for y in 0..ny {
            col[y] = g[y * nx + x];
        }
        edt_line(&col, &mut out[..ny]);
        for y in 0..ny {
            g[y * nx + x] = out[y];
        }
    }
    let mut row = vec![0.0; nx];
    for y in 0..ny {
        row.copy_from_slice(&g[y * nx..(y + 1) * nx]);
        edt_line(&row, &mut out[..nx]);
        g[y * nx..(y + 1) * nx].copy_from_slice(&out[..nx]);
    }
    g
}

/// Catmull-Rom weights at `t` and their derivatives.
fn catmull_rom(t: f64) -> ([f64; 4], [f64; 4]) {
    let [w, dw, _] = super::sampled::weights(t);
    (w, dw)
}

impl Flange {
    /// The bytes [`Flange::within`] takes for a die of bounds `die_bounds`.
    pub fn raster_bytes(die_bounds: ([f64; 3], [f64; 3]), spacing: f64, reach: Box2) -> f64 {
        let (_, kept) = cells(die_bounds, spacing, reach);
        kept[0][1] * kept[1][1] * BYTES_PER_CELL
    }

    /// The face of `die` (a checked surface) at plan spacing `spacing`, rasterised within the
    /// plan box `reach` only; refused when no triangle lies in z = 0 facing up, or none within
    /// `reach`.
    pub fn within(die: &TriSurface, spacing: f64, reach: Box2) -> Result<Flange, NoFlange> {
        let (origin, kept) = cells(die.bounds(), spacing, reach);
        let first = [0, 1].map(|a| kept[a][0] as usize);
        let dims = [0, 1].map(|a| kept[a][1] as usize);
        let mut face = vec![false; dims[0] * dims[1]];
        let mut any_face = false;
        let mut area = 0.0;
        let grid = Grid {
            origin,
            first,
            dims,
            spacing,
        };
        for t in 0..die.triangles.len() {
            if let Some(half_cross) = grid.cover(die.corners(t), &mut face) {
                area += half_cross;
                any_face = true;
            }
        }
        if area <= 0.0 || !any_face {
            return Err(NoFlange::NoFace);
        }
        if !face.iter().any(|&f| f) {
            return Err(NoFlange::OutsideReach);
        }
        let to_face = edt(dims, &|i| face[i]);
        let to_open = edt(dims, &|i| !face[i]);
        let values = (0..face.len())
            .map(|i| {
                if face[i] {
                    (to_open[i].sqrt() - 0.5) * spacing
                } else {
                    -(to_face[i].sqrt() - 0.5) * spacing
                }
            })
            .collect();
        Ok(Flange {
            origin,
            first,
            spacing,
            dims,
            values,
            face_area_mm2: area,
        })
    }

    fn value(&self, i: isize, j: isize) -> f64 {
        let i = i.clamp(0, self.dims[0] as isize - 1) as usize;
        let j = j.clamp(0, self.dims[1] as isize - 1) as usize;
        self.values[j * self.dims[0] + i]
    }

    /// The signed plan distance to the face's edge at `(x, y)` (positive on the face), mm, and
    /// its gradient.
    pub fn distance(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        let gx = (x - self.origin[0]) / self.spacing - 0.5 - self.first[0] as f64;
        let gy = (y - self.origin[1]) / self.spacing - 0.5 - self.first[1] as f64;
        if !gx.is_finite() || !gy.is_finite() {
            return (f64::NEG_INFINITY, [0.0; 2]);
        }
        let (bx, by) = (gx.floor(), gy.floor());
        let (wx, dwx) = catmull_rom(gx - bx);
        let (wy, dwy) = catmull_rom(gy - by);
        let (mut f, mut fx, mut fy) = (0.0, 0.0, 0.0);
        for (b, (&w_y, &dw_y)) in wy.iter().zip(&dwy).enumerate() {
            for (a, (&w_x, &dw_x)) in wx.iter().zip(&dwx).enumerate() {
                let s = self.value(bx as isize + a as isize - 1, by as isize + b as isize - 1);
                f += w_x * w_y * s;
                fx += dw_x * w_y * s;
                fy += w_x * dw_y * s;
            }
        }
        (f, [fx / self.spacing, fy / self.spacing])
    }

    /// The grid: origin of cell (0, 0)'s corner, spacing, cells along x and y, and the signed
    /// distance at each cell centre (row-major in x), for drawing the face's edge.
    pub fn grid(&self) -> ([f64; 2], f64, [usize; 2], &[f64]) {
        let corner = [0, 1].map(|a| self.origin[a] + self.first[a] as f64 * self.spacing);
        (corner, self.spacing, self.dims, &self.values)
    }

    /// Half extents of the opening along the axes through the origin (where the face starts
    /// along ±x and ±y, the larger of each pair), mm.
    pub fn opening_half(&self) -> [f64; 2] {
        let step = 0.25 * self.spacing;
        let reach = |dir: [f64; 2]| {
            let mut s = 0.0;
            let limit = (self.dims[0] + self.dims[1]) as f64 * self.spacing;
            while s < limit && self.distance(s * dir[0], s * dir[1]).0 < 0.0 {
                s += step;
            }
            s
        };
        [
            reach([1.0, 0.0]).max(reach([-1.0, 0.0])),
            reach([0.0, 1.0]).max(reach([0.0, -1.0])),
        ]
    }
}

/// The plan grid a flange is sampled on: its origin, first kept cell, kept cells per axis and
/// spacing, mm.
struct Grid {
    origin: [f64; 2],
    first: [usize; 2],
    dims: [usize; 2],
    spacing: f64,
}

impl Grid {
    /// Marks in `face` the cells whose centres triangle `[a, b, c]` covers, when it lies in the
    /// die's face (within [`FACE_TOL_MM`] of z = 0, facing up within 1°); its area in plan,
    /// mm², or `None` for a triangle off the face.
    fn cover(&self, [a, b, c]: [[f64; 3]; 3], face: &mut [bool]) -> Option<f64> {
        if [a, b, c].iter().any(|p| p[2].abs() > FACE_TOL_MM) {
            return None;
        }
        let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
        let cross = u[0] * v[1] - u[1] * v[0];
        let len = {
            let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
        };
        if len == 0.0 || cross / len < 1f64.to_radians().cos() {
            return None;
        }
        let (origin, first, dims, spacing) = (self.origin, self.first, self.dims, self.spacing);
        if dims[0] == 0 || dims[1] == 0 {
            return Some(0.5 * cross);
        }
        // Cells whose centres the triangle covers (counted from the first kept).
        let cell = |x: f64, a: usize| ((x - origin[a]) / spacing - 0.5).floor() - first[a] as f64;
        let (x0, x1) = (
            cell(a[0].min(b[0]).min(c[0]), 0),
            cell(a[0].max(b[0]).max(c[0]), 0) + 1.0,
        );
        let (y0, y1) = (
            cell(a[1].min(b[1]).min(c[1]), 1),
            cell(a[1].max(b[1]).max(c[1]), 1) + 1.0,
        );
        for j in y0.max(0.0) as usize..=(y1.max(0.0) as usize).min(dims[1] - 1) {
            for i in x0.max(0.0) as usize..=(x1.max(0.0) as usize).min(dims[0] - 1) {
                let p = [
                    origin[0] + ((first[0] + i) as f64 + 0.5) * spacing - a[0],
                    origin[1] + ((first[1] + j) as f64 + 0.5) * spacing - a[1],
                ];
                // Barycentric test (the triangle winds counter-clockwise in plan).
                let s = (p[0] * v[1] - p[1] * v[0]) / cross;
                let r = (u[0] * p[1] - u[1] * p[0]) / cross;
                let eps = 1e-12;
                if s >= -eps && r >= -eps && s + r <= 1.0 + eps {
                    face[j * dims[0] + i] = true;
                }
            }
        }
        Some(0.5 * cross)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distance_transform_is_exact_on_a_line_and_a_plane() {
        let f = [
            f64::INFINITY,
            0.0,
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
            0.0,
        ];
        let mut out = [0.0; 6];
        edt_line(&f, &mut out);
        assert_eq!(out, [1.0, 0.0, 1.0, 4.0, 1.0, 0.0]);
        let dims = [7, 5];
        let g = edt(dims, &|i| i == 2 * 7 + 3);
        for j in 0..5 {
            for i in 0..7 {
                let want = (i as f64 - 3.0).powi(2) + (j as f64 - 2.0).powi(2);
                assert_eq!(g[j * 7 + i], want, "{i} {j}");
            }
        }
    }
}
