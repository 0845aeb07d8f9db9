//! The double dome: a punch of two spherical domes joined smoothly with a saddle between them
//! (a benchmark shape of composite forming), and its die.
//!
//! ```text
//!   plan (z = 0 up)              side (section y = 0)
//!     ╭───╮   ╭───╮               │                 │   walls vertical above the
//!    │     ╰─╯     │               │                 │   domes' equator z = R
//!    │     ╭─╮     │                ╲      ╭─╮      ╱
//!     ╰───╯   ╰───╯                  ╰────╯   ╰────╯    lowest points z = 0 at x = ±c
//! ```
//!
//! The punch's field is the polynomial smooth minimum of the two spheres' distances (radius
//! R, centres at x = ±c, z = R), taken at z clamped to the equator so that the body above it
//! is the plan outline extruded upward. The die is a plate (face z = 0) whose opening is that
//! outline offset by the clearance, its edge rounded with the entry radius, built as the
//! analytic dies are (`rounded_intersection`).

use super::capped::capped_surface;
use super::surface::TriSurface;
use super::{Distance, rounded_intersection};

/// A double-dome punch and its die, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubleDome {
    /// Radius R of each dome.
    pub radius_mm: f64,
    /// The domes' centres lie at x = ±`centre_x_mm`.
    pub centre_x_mm: f64,
    /// Width k of the smooth minimum: the domes blend where their fields differ by less.
    pub blend_mm: f64,
    /// Gap between the punch's plan outline and the die opening.
    pub clearance_mm: f64,
    /// Radius of the die opening's rounded edge.
    pub entry_radius_mm: f64,
}

/// Where the tools are cut to make them closed solids, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Caps {
    /// The punch is cut at this height (stroke + 10 mm).
    pub punch_top_mm: f64,
    /// The die is cut at these half sides in plan.
    pub die_half_mm: [f64; 2],
    /// The die is cut at this depth below its face.
    pub die_depth_mm: f64,
}

/// The punch's capping box reaches this far beyond its plan outline, mm (it does not cut it).
const PUNCH_PLAN_MARGIN_MM: f64 = 5.0;

impl DoubleDome {
    /// Domes of radius 30 mm at x = ±22 mm blended over 10 mm; clearance 2 mm, entry radius
    /// 6 mm.
    pub const STANDARD: DoubleDome = DoubleDome {
        radius_mm: 30.0,
        centre_x_mm: 22.0,
        blend_mm: 10.0,
        clearance_mm: 2.0,
        entry_radius_mm: 6.0,
    };

    /// The caps for a blank of about 220 × 160 mm drawn by 25 mm: the punch cut at
    /// z = 25 + 10 mm, the die at half sides 125 × 95 mm and 35 mm deep.
    pub const STANDARD_CAPS: Caps = Caps {
        punch_top_mm: 35.0,
        die_half_mm: [125.0, 95.0],
        die_depth_mm: 35.0,
    };

    /// The smooth minimum of the two spheres' distances at `p` with `z` clamped to the
    /// equator, and its gradient.
    fn domes(&self, p: [f64; 3]) -> (f64, [f64; 3]) {
        let r = self.radius_mm;
        let z = p[2].min(r);
        let sphere = |cx: f64| {
            let v = [p[0] - cx, p[1], z - r];
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let g = if l > 0.0 {
                v.map(|c| c / l)
            } else {
                [0.0, 0.0, -1.0]
            };
            (l - r, g)
        };
        let (a, b) = (sphere(-self.centre_x_mm), sphere(self.centre_x_mm));
        smooth_min(a, b, self.blend_mm)
    }

    /// The punch's signed field at `p` (negative inside; the distance itself off the blend,
    /// a slight underestimate in it) and its outward normal. Lowest points: z = 0 at
    /// x = ±`centre_x_mm`, y = 0.
    pub fn punch(&self, p: [f64; 3]) -> Distance {
        let (d, g) = self.domes(p);
        Distance { d, n: unit(g) }
    }

    /// The plan field of the die opening (positive outside the opening, on the die) and its
    /// gradient: the punch's plan outline (its section at the equator) offset by the
    /// clearance. The blend's field grows slower than the distance, so it is divided by its
    /// gradient's length (at least 0.5, far from the outline) to offset by the clearance
    /// itself.
    fn opening(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        let (g, grad) = self.domes([x, y, self.radius_mm]);
        let slope = (grad[0] * grad[0] + grad[1] * grad[1]).sqrt();
        let n = if slope > 0.0 {
            [grad[0] / slope, grad[1] / slope]
        } else {
            [1.0, 0.0]
        };
        (g / slope.max(0.5) - self.clearance_mm, n)
    }

    /// The die's signed distance at `p` and its outward normal: material below z = 0 outside
    /// the opening, the opening's edge rounded with the entry radius.
    pub fn die(&self, p: [f64; 3]) -> Distance {
        let (d, g) = self.opening(p[0], p[1]);
        rounded_intersection(
            -d,
            [-g[0], -g[1], 0.0],
            p[2],
            [0.0, 0.0, 1.0],
            self.entry_radius_mm,
        )
    }

    /// Half extents of the punch's plan outline, mm.
    pub fn punch_half_mm(&self) -> [f64; 2] {
        [self.centre_x_mm + self.radius_mm, self.radius_mm]
    }

    /// The punch and the die cut by `caps` and tessellated on grids of `punch_spacing_mm`
    /// and `die_spacing_mm` (see [`capped_surface`]).
    pub fn surfaces(
        &self,
        caps: &Caps,
        punch_spacing_mm: f64,
        die_spacing_mm: f64,
    ) -> (TriSurface, TriSurface) {
        let half = self.punch_half_mm().map(|h| h + PUNCH_PLAN_MARGIN_MM);
        let top = caps.punch_top_mm;
        let punch = |p: [f64; 3]| self.punch(p).d;
        let die = |p: [f64; 3]| self.die(p).d;
        let depth = caps.die_depth_mm;
        (
            capped_surface(&punch, true, half, [-top, top], punch_spacing_mm),
            capped_surface(
                &die,
                false,
                caps.die_half_mm,
                [-depth, depth],
                die_spacing_mm,
            ),
        )
    }
}

/// The polynomial smooth minimum of two fields with their gradients, blended over `k`:
/// `min(a, b) − h² k/4`, `h = max(k − |a − b|, 0)/k`.
fn smooth_min(a: (f64, [f64; 3]), b: (f64, [f64; 3]), k: f64) -> (f64, [f64; 3]) {
    let h = (k - (a.0 - b.0).abs()).max(0.0) / k;
    let (low, high) = if a.0 <= b.0 { (a, b) } else { (b, a) };
    let g = [0, 1, 2].map(|i| (1.0 - 0.5 * h) * low.1[i] + 0.5 * h * high.1[i]);
    (low.0 - 0.25 * h * h * k, g)
}

fn unit(g: [f64; 3]) -> [f64; 3] {
    let l = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    if l > 0.0 {
        g.map(|c| c / l)
    } else {
        [0.0, 0.0, -1.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DD: DoubleDome = DoubleDome::STANDARD;

    /// The root of `f` along the ray from the origin at angle `theta`, between 0 and `far`.
    fn on_ray(f: &dyn Fn(f64, f64) -> f64, theta: f64, far: f64) -> [f64; 2] {
        let (c, s) = (theta.cos(), theta.sin());
        let (mut lo, mut hi) = (0.0, far);
        assert!(f(0.0, 0.0) < 0.0 && f(far * c, far * s) > 0.0);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if f(mid * c, mid * s) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        [lo * c, lo * s]
    }

    #[test]
    fn two_domes_with_a_saddle_between_them() {
        for x in [-22.0, 22.0] {
            let tip = DD.punch([x, 0.0, 0.0]);
            assert!(tip.d.abs() < 1e-12, "{x}: {tip:?}");
            assert!(
                tip.n
                    .iter()
                    .zip([0.0, 0.0, -1.0])
                    .all(|(a, b)| (a - b).abs() < 1e-12)
            );
        }
        // On the axis x = 0 the blend meets the surface where each sphere's distance is
        // k/4: z = R − sqrt((R + k/4)² − c²).
        let saddle = 30.0 - (32.5f64.powi(2) - 22.0f64.powi(2)).sqrt();
        assert!(DD.punch([0.0, 0.0, saddle]).d.abs() < 1e-12);
        assert!((5.0..7.0).contains(&saddle), "saddle at {saddle} mm");
        // A saddle: the surface falls along x (to the domes) and rises along y.
        let height = |x: f64, y: f64| {
            let (mut lo, mut hi) = (-1.0, 30.0);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if DD.punch([x, y, mid]).d > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        assert!(height(3.0, 0.0) < saddle - 0.1 && height(0.0, 3.0) > saddle + 0.1);
        // Vertical walls above the equator.
        for p in [[50.0, 5.0], [0.0, 23.0], [-30.0, -29.0]] {
            let (a, b) = (DD.punch([p[0], p[1], 31.0]), DD.punch([p[0], p[1], 80.0]));
            assert_eq!(a, b);
            assert_eq!(a.n[2], 0.0);
        }
    }

    #[test]
    fn the_die_opening_is_the_outline_offset_by_the_clearance() {
        let outline_at = |x: f64, y: f64| DD.domes([x, y, 30.0]).0;
        let outline: Vec<[f64; 2]> = (0..4000)
            .map(|i| on_ray(&outline_at, i as f64 * std::f64::consts::TAU / 4000.0, 60.0))
            .collect();
        let opening_at = |x: f64, y: f64| DD.opening(x, y).0;
        let (mut least, mut most) = (f64::INFINITY, 0.0f64);
        for i in 0..400 {
            let w = on_ray(
                &opening_at,
                (i as f64 + 0.5) * std::f64::consts::TAU / 400.0,
                70.0,
            );
            let gap = outline
                .iter()
                .map(|o| ((o[0] - w[0]).powi(2) + (o[1] - w[1]).powi(2)).sqrt())
                .fold(f64::INFINITY, f64::min);
            least = least.min(gap);
            most = most.max(gap);
        }
        assert!(
            least > 1.95 && most < 2.05,
            "the gap runs from {least} to {most} mm"
        );
    }

    #[test]
    fn the_die_face_is_z_0_with_a_rounded_entry() {
        // On the face beyond the entry radius: the distance is z.
        for p in [[100.0, 0.0], [0.0, 60.0], [-90.0, 80.0]] {
            for z in [-3.0, 0.0, 2.0] {
                assert_eq!(DD.die([p[0], p[1], z]).d, z);
            }
        }
        // Down the opening's wall, below the rounded edge: the plan distance to the offset.
        let wall = on_ray(&|x, y| DD.opening(x, y).0, 0.0, 70.0);
        let d = DD.die([wall[0] - 1.0, wall[1], -20.0]).d;
        assert!((d - 1.0).abs() < 1e-6, "{d}");
        // The rounded edge: the corner point of face and wall is entry radius·(√2 − 1) out.
        let corner = DD.die([wall[0], wall[1], 0.0]).d;
        assert!(
            (corner - 6.0 * (2f64.sqrt() - 1.0)).abs() < 1e-6,
            "{corner}"
        );
    }

    #[test]
    fn the_tools_tessellate_closed_with_the_right_topology() {
        let (punch, die) = DD.surfaces(&DoubleDome::STANDARD_CAPS, 2.0, 2.0);
        let euler = |s: &TriSurface| {
            s.vertices.len() as i64 - (3 * s.triangles.len() / 2) as i64 + s.triangles.len() as i64
        };
        punch.check().unwrap();
        die.check().unwrap();
        assert_eq!(euler(&punch), 2, "the punch is a ball");
        assert_eq!(euler(&die), 0, "the die is a plate with a hole");
        let (lo, hi) = punch.bounds();
        assert!(
            lo[2].abs() < 1e-6 && (hi[2] - 35.0).abs() < 1e-9,
            "{lo:?} {hi:?}"
        );
        let (lo, hi) = die.bounds();
        assert!(hi[2].abs() < 1e-9, "{hi:?}");
        assert!((lo[0] + 125.0).abs() < 1e-9 && (hi[1] - 95.0).abs() < 1e-9);
        assert!((lo[2] + 35.0).abs() < 1e-9);
    }
}
