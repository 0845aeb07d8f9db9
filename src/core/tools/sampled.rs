//! A mesh tool's signed distance made smooth: the exact distance to the triangles
//! ([`ExactDistance`]) sampled on a lattice of spacing `h` and interpolated by tricubic
//! Catmull-Rom splines. The interpolant is C1 everywhere (its gradient, the contact normal,
//! is continuous across the facets' edges and the lattice's cells), it reproduces planes and
//! quadratics exactly (a flat face has zero curvature) and it is third-order accurate on a
//! smooth surface.
//!
//! Samples are computed when first needed and kept (the lattice is paged, 8³ samples a page,
//! so a tool's memory grows with the part of it the fabric visits). Far from the surface no
//! sample is needed: a page's centre distance `d_c` bounds every point's, `|d| ≥ |d_c| − |p − c|`,
//! and where that bound exceeds the `band` the bound itself is the answer. Outside the lattice
//! the distance to the tool's bounding box is (outside the box), or the exact distance (inside
//! it). Contact acts within a small gap of the surface, well inside the band, so these bounds
//! never carry a force.
//!
//! The lattice covers the tool's bounding box grown by a margin, but only where the fabric can
//! reach ([`SampledDistance::within`]): a die plate far wider than the blank keeps no pages
//! for the part no fabric visits. The pages kept are whole pages of the full lattice (the same
//! nodes, the same page centres), so that clipping changes no value.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

use super::nearest::ExactDistance;
use super::surface::TriSurface;

type V3 = [f64; 3];
type M3 = [[f64; 3]; 3];

/// Samples per page side.
const P: usize = 8;
/// A sample not computed yet (a NaN no distance takes). Samples are kept in single precision
/// (7 digits: 1e-5 mm on a 100 mm tool), which halves the memory the interpolation reads.
const UNSET: u32 = u32::MAX;

/// What a page's centre tells of the page.
#[derive(Clone, Copy)]
struct PageInfo {
    /// The exact distance and outward direction at the page's centre.
    d: f64,
    n: V3,
    /// The plane `n·x = c` that is the whole surface near the page, when it is one (a die's
    /// face, a punch's flat nose): there the distance is exactly `n·p − c`, which is what the
    /// interpolant of its samples would give, at no sampling cost.
    plane: Option<(V3, f64)>,
}

struct Page {
    centre: OnceLock<PageInfo>,
    samples: OnceLock<Box<[AtomicU32]>>,
}

/// A box, mm: its lowest and highest corners.
pub type Box3 = (V3, V3);

/// All of space, for a lattice over the whole tool.
pub const EVERYWHERE: Box3 = ([f64::NEG_INFINITY; 3], [f64::INFINITY; 3]);

/// The nodes of the lattice kept, per axis (as `f64`, so that a lattice too large to allocate
/// is measured without overflow): the full lattice's first node `origin`, the first node kept
/// (a whole number of pages in) and how many are kept.
struct Layout {
    origin: V3,
    first: [f64; 3],
    nodes: [f64; 3],
}

impl Layout {
    fn of(bounds: Box3, spacing: f64, margin: f64, reach: Box3) -> Layout {
        let (lo, hi) = bounds;
        let origin = lo.map(|v| v - margin);
        let full = [0, 1, 2].map(|i| ((hi[i] - lo[i] + 2.0 * margin) / spacing).ceil() + 1.0);
        // The nodes the stencils of points in `reach` use (one cell more each side).
        let from = [0, 1, 2].map(|i| ((reach.0[i] - origin[i]) / spacing).floor() - 2.0);
        let to = [0, 1, 2].map(|i| ((reach.1[i] - origin[i]) / spacing).ceil() + 2.0);
        let p = P as f64;
        let first = [0, 1, 2].map(|i| ((from[i].max(0.0) / p).floor() * p).min(full[i]));
        let last = [0, 1, 2].map(|i| to[i].min(full[i] - 1.0));
        let nodes = [0, 1, 2].map(|i| (last[i] - first[i] + 1.0).max(0.0));
        Layout {
            origin,
            first,
            nodes,
        }
    }

    fn pages(&self) -> [f64; 3] {
        self.nodes.map(|n| (n / P as f64).ceil())
    }
}

/// The smooth signed distance of a closed triangle surface.
pub struct SampledDistance {
    exact: ExactDistance,
    spacing: f64,
    band: f64,
    /// The full lattice's first node (the nodes kept start `first` nodes further).
    origin: V3,
    first: [usize; 3],
    nodes: [usize; 3],
    pages_per_axis: [usize; 3],
    pages: Vec<Page>,
    lo: V3,
    hi: V3,
}

/// The distance at a point, its gradient and (when asked) its Hessian.
#[derive(Clone, Copy, Debug)]
pub struct Evaluation {
    pub d: f64,
    pub n: V3,
    pub hessian: Option<M3>,
}

/// Catmull-Rom weights at `t ∈ [0, 1)` for the nodes −1, 0, 1, 2, and their first and second
/// derivatives in `t`.
pub(super) fn weights(t: f64) -> [[f64; 4]; 3] {
    let (t2, t3) = (t * t, t * t * t);
    [
        [
            0.5 * (-t3 + 2.0 * t2 - t),
            0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
            0.5 * (-3.0 * t3 + 4.0 * t2 + t),
            0.5 * (t3 - t2),
        ],
        [
            0.5 * (-3.0 * t2 + 4.0 * t - 1.0),
            0.5 * (9.0 * t2 - 10.0 * t),
            0.5 * (-9.0 * t2 + 8.0 * t + 1.0),
            0.5 * (3.0 * t2 - 2.0 * t),
        ],
        [2.0 - 3.0 * t, 9.0 * t - 5.0, 4.0 - 9.0 * t, 3.0 * t - 1.0],
    ]
}

impl SampledDistance {
    /// The lattice of spacing `spacing` over the surface's bounding box grown by `margin`
    /// (which must exceed `band` by three spacings), exact within `band` of the surface.
    pub fn new(surface: &TriSurface, spacing: f64, band: f64, margin: f64) -> SampledDistance {
        Self::within(surface, spacing, band, margin, EVERYWHERE)
    }

    /// The bytes the lattice's page table of [`SampledDistance::within`] takes (allocated at
    /// once), and those its samples would take over `area_mm2` of surface (allocated as the
    /// fabric visits it: a sheet crosses pages obliquely, so about four pages deep).
    pub fn table_bytes(
        bounds: Box3,
        spacing: f64,
        band: f64,
        margin: f64,
        reach: Box3,
        area_mm2: f64,
    ) -> (f64, f64) {
        let margin = margin.max(band + 3.0 * spacing);
        let pages = Layout::of(bounds, spacing, margin, reach).pages();
        let table = pages.iter().product::<f64>() * size_of::<Page>() as f64;
        let page_side = P as f64 * spacing;
        let visited = (4.0 * area_mm2 / (page_side * page_side)).min(pages.iter().product());
        (table, visited * (P * P * P * 4 + 16) as f64)
    }

    /// [`SampledDistance::new`] keeping only the pages that points in `reach` use: elsewhere
    /// (where no fabric goes) the exact distance is computed when asked.
    pub fn within(
        surface: &TriSurface,
        spacing: f64,
        band: f64,
        margin: f64,
        reach: Box3,
    ) -> SampledDistance {
        let (lo, hi) = surface.bounds();
        let margin = margin.max(band + 3.0 * spacing);
        let layout = Layout::of((lo, hi), spacing, margin, reach);
        let origin = layout.origin;
        let first = layout.first.map(|v| v as usize);
        let nodes = layout.nodes.map(|v| v as usize);
        let pages_per_axis = nodes.map(|n| n.div_ceil(P));
        let count = pages_per_axis.iter().product();
        let pages = (0..count)
            .map(|_| Page {
                centre: OnceLock::new(),
                samples: OnceLock::new(),
            })
            .collect();
        SampledDistance {
            exact: ExactDistance::new(surface),
            spacing,
            band,
            origin,
            first,
            nodes,
            pages_per_axis,
            pages,
            lo,
            hi,
        }
    }

    /// The exact distance (no smoothing), for checks and placement.
    pub fn exact(&self) -> &ExactDistance {
        &self.exact
    }

    /// The full lattice's first node, mm (every node, kept or not, at whole spacings from
    /// it).
    pub fn lattice_origin(&self) -> V3 {
        self.origin
    }

    /// The lattice spacing, mm.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    fn page_index(&self, page: [usize; 3]) -> usize {
        let a = self.pages_per_axis;
        (page[2] * a[1] + page[1]) * a[0] + page[0]
    }

    /// The exact distance at a page's centre, and the plane that is the surface all around
    /// it if one is: every triangle within reach of the page's interpolation stencils (the page
    /// grown by the band and two cells) and of their nearest points (as much again) coplanar.
    fn page_info(&self, centre: V3) -> PageInfo {
        let q = self.exact.query(centre);
        let half = 0.5 * P as f64 * self.spacing;
        let reach = half + 2.0 * (self.band + 2.0 * self.spacing);
        let near = q.d.abs() <= half * 3f64.sqrt() + self.band + 4.0 * self.spacing;
        let plane = near
            .then(|| {
                self.exact
                    .plane_within(centre.map(|v| v - reach), centre.map(|v| v + reach))
            })
            .flatten();
        PageInfo {
            d: q.d,
            n: q.n,
            plane,
        }
    }

    fn page_samples(&self, page: usize) -> &[AtomicU32] {
        self.pages[page]
            .samples
            .get_or_init(|| (0..P * P * P).map(|_| AtomicU32::new(UNSET)).collect())
    }

    /// The exact distance at lattice node `i` (counted from the first node kept), kept in
    /// `samples[local]`.
    fn compute(&self, samples: &[AtomicU32], local: usize, i: [usize; 3]) -> f64 {
        let x = [0, 1, 2].map(|a| self.origin[a] + (self.first[a] + i[a]) as f64 * self.spacing);
        let d = self.exact.query(x).d;
        samples[local].store((d as f32).to_bits(), Ordering::Relaxed);
        d
    }

    /// Off the lattice: the lower bound from the bounding box outside it, the exact distance
    /// inside (where a lattice kept only where the fabric reaches leaves the tool).
    fn off_lattice(&self, p: V3) -> Evaluation {
        let in_box = (0..3).all(|i| p[i] >= self.lo[i] && p[i] <= self.hi[i]);
        if in_box {
            let q = self.exact.query(p);
            return Evaluation {
                d: q.d,
                n: q.n,
                hessian: None,
            };
        }
        let v = [0, 1, 2].map(|i| p[i] - p[i].clamp(self.lo[i], self.hi[i]));
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        Evaluation {
            d: l,
            n: if l > 0.0 {
                v.map(|c| c / l)
            } else {
                [0.0, 0.0, 1.0]
            },
            hessian: None,
        }
    }

    /// The smooth signed distance at `p`, its gradient, and its Hessian when `hessian`.
    pub fn evaluate(&self, p: V3, hessian: bool) -> Evaluation {
        let h = self.spacing;
        // Counted from the first node kept (exact: a whole number off a larger one).
        let g = [0, 1, 2].map(|a| (p[a] - self.origin[a]) / h - self.first[a] as f64);
        let base = g.map(|v| v.floor());
        let inside = (0..3).all(|a| base[a] >= 1.0 && base[a] + 2.0 <= self.nodes[a] as f64 - 1.0);
        if !inside || g.iter().any(|v| !v.is_finite()) {
            return self.off_lattice(p);
        }
        let cell = base.map(|v| v as usize);
        // Far from the surface: the page centre's distance bounds the point's.
        let page = cell.map(|v| v / P);
        let centre = [0, 1, 2]
            .map(|a| self.origin[a] + ((self.first[a] + page[a] * P) as f64 + 0.5 * P as f64) * h);
        let info = *self.pages[self.page_index(page)]
            .centre
            .get_or_init(|| self.page_info(centre));
        let off = [0, 1, 2].map(|a| p[a] - centre[a]);
        let bound = info.d.abs() - (off[0] * off[0] + off[1] * off[1] + off[2] * off[2]).sqrt();
        if bound > self.band {
            return Evaluation {
                d: bound.copysign(info.d),
                n: info.n,
                hessian: None,
            };
        }
        if let Some((n, c)) = info.plane {
            return Evaluation {
                d: n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - c,
                n,
                hessian: hessian.then_some([[0.0; 3]; 3]),
            };
        }
        let w = [0, 1, 2].map(|a| weights(g[a] - base[a]));
        self.interpolate(cell, &w, hessian)
    }

    /// The 4 × 4 × 4 samples around `cell` (x fastest), computing those not known yet.
    fn stencil(&self, cell: [usize; 3]) -> [f64; 64] {
        let idx = |a: usize| [0, 1, 2, 3].map(|o| cell[a] + o - 1);
        let (ix, iy, iz) = (idx(0), idx(1), idx(2));
        let a = self.pages_per_axis;
        let mut out = [0.0; 64];
        let mut n = 0;
        for &z in &iz {
            for &y in &iy {
                let row = ((z / P) * a[1] + y / P) * a[0];
                let local_row = ((z % P) * P + y % P) * P;
                let mut current: Option<(usize, &[AtomicU32])> = None;
                for &x in &ix {
                    let page = row + x / P;
                    let samples = match current {
                        Some((p, s)) if p == page => s,
                        _ => {
                            let s = self.page_samples(page);
                            current = Some((page, s));
                            s
                        }
                    };
                    let local = local_row + x % P;
                    let bits = samples[local].load(Ordering::Relaxed);
                    out[n] = if bits != UNSET {
                        f32::from_bits(bits) as f64
                    } else {
                        self.compute(samples, local, [x, y, z])
                    };
                    n += 1;
                }
            }
        }
        out
    }

    fn interpolate(&self, cell: [usize; 3], w: &[[[f64; 4]; 3]; 3], hessian: bool) -> Evaluation {
        let h = self.spacing;
        let s = self.stencil(cell);
        // Along x: for each (j, k) the value and its first and second x-derivatives.
        let mut ax = [[[0.0; 3]; 4]; 4];
        for (k, axk) in ax.iter_mut().enumerate() {
            for (j, axjk) in axk.iter_mut().enumerate() {
                let row = &s[16 * k + 4 * j..16 * k + 4 * j + 4];
                for (o, v) in axjk.iter_mut().enumerate() {
                    let wo = &w[0][o];
                    *v = wo[0] * row[0] + wo[1] * row[1] + wo[2] * row[2] + wo[3] * row[3];
                }
            }
        }
        // Along y: [f, fy, fyy, fx, fxy, fxx] for each k.
        let mut by = [[0.0; 6]; 4];
        for k in 0..4 {
            for j in 0..4 {
                let a = ax[k][j];
                let (wy, wy1, wy2) = (w[1][0][j], w[1][1][j], w[1][2][j]);
                let b = &mut by[k];
                b[0] += wy * a[0];
                b[1] += wy1 * a[0];
                b[2] += wy2 * a[0];
                b[3] += wy * a[1];
                b[4] += wy1 * a[1];
                b[5] += wy * a[2];
            }
        }
        // Along z.
        let mut f = [0.0; 10]; // f, fx, fy, fz, fxx, fyy, fzz, fxy, fxz, fyz
        for (k, b) in by.iter().enumerate() {
            let (wz, wz1, wz2) = (w[2][0][k], w[2][1][k], w[2][2][k]);
            f[0] += wz * b[0];
            f[1] += wz * b[3];
            f[2] += wz * b[1];
            f[3] += wz1 * b[0];
            f[4] += wz * b[5];
            f[5] += wz * b[2];
            f[6] += wz2 * b[0];
            f[7] += wz * b[4];
            f[8] += wz1 * b[3];
            f[9] += wz1 * b[1];
        }
        let n = [f[1] / h, f[2] / h, f[3] / h];
        let hess = hessian.then(|| {
            let s = 1.0 / (h * h);
            [
                [f[4] * s, f[7] * s, f[8] * s],
                [f[7] * s, f[5] * s, f[9] * s],
                [f[8] * s, f[9] * s, f[6] * s],
            ]
        });
        Evaluation {
            d: f[0],
            n,
            hessian: hess,
        }
    }
}
