//! The die opening in plan, as a polyline: what the maps draw dashed.

use super::Tooling;

impl Tooling {
    /// The die opening in plan as a closed polyline, mm.
    pub fn die_opening_outline(&self) -> Vec<[f64; 2]> {
        const N: usize = 24; // points per quarter turn
        let half = self.opening_half();
        let mut pts = Vec::with_capacity(4 * N + 1);
        match self {
            &Tooling::Box { r, clearance, .. } => {
                let rc = (r + clearance).min(half[0]).min(half[1]);
                let centres = [
                    [half[0] - rc, half[1] - rc],
                    [-(half[0] - rc), half[1] - rc],
                    [-(half[0] - rc), -(half[1] - rc)],
                    [half[0] - rc, -(half[1] - rc)],
                ];
                for (k, c) in centres.iter().enumerate() {
                    for i in 0..=N {
                        let t = (k as f64 + i as f64 / N as f64) * std::f64::consts::FRAC_PI_2;
                        pts.push([c[0] + rc * t.cos(), c[1] + rc * t.sin()]);
                    }
                }
            }
            &Tooling::Ellipsoid {
                axes, clearance, ..
            } => {
                let (a, b) = (axes[0], axes[1]);
                for i in 0..4 * N {
                    let t = i as f64 / (4 * N) as f64 * std::f64::consts::TAU;
                    let (c, s) = (t.cos(), t.sin());
                    let n = [b * c, a * s];
                    let l = (n[0] * n[0] + n[1] * n[1]).sqrt();
                    pts.push([a * c + clearance * n[0] / l, b * s + clearance * n[1] / l]);
                }
            }
            Tooling::Hemisphere { .. } => {
                for i in 0..4 * N {
                    let t = i as f64 / (4 * N) as f64 * std::f64::consts::TAU;
                    pts.push([half[0] * t.cos(), half[1] * t.sin()]);
                }
            }
            Tooling::Mesh { die, .. } => {
                // Where the face begins along rays from the centre (an opening star-shaped
                // about it), by bisection of the flange's distance.
                if let Some(f) = die.flange.as_ref() {
                    let far = 2.0
                        * (die.bounds.1[0] - die.bounds.0[0])
                            .max(die.bounds.1[1] - die.bounds.0[1]);
                    for i in 0..16 * N {
                        let t = i as f64 / (16 * N) as f64 * std::f64::consts::TAU;
                        let (c, s) = (t.cos(), t.sin());
                        let on_face = |r: f64| f.distance(r * c, r * s).0 >= 0.0;
                        let mut r = 0.0;
                        let step = 0.5;
                        while r < far && !on_face(r + step) {
                            r += step;
                        }
                        let (mut a, mut b) = (r, r + step);
                        for _ in 0..30 {
                            let m = 0.5 * (a + b);
                            if on_face(m) { b = m } else { a = m }
                        }
                        pts.push([b * c, b * s]);
                    }
                }
            }
        }
        if let Some(&first) = pts.first() {
            pts.push(first);
        }
        pts
    }
}
