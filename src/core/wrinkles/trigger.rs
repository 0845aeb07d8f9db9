//! The trigger of a buckling problem: a perfectly flat blank under in-plane compression is
//! in equilibrium flat (a saddle once compression passes the critical load), and Newton's
//! method, started flat, stays flat. A real blank is never perfect; the model says how it is
//! not: a small out-of-plane pressure `q s(x, y)` held through the whole stroke, `s` a seeded
//! random field of unit root-mean-square made of [`MODES`] plane waves whose wavelengths lie
//! between [`WAVELENGTH_MM`] (in millimetres, not elements, so the trigger is the same on every
//! mesh). The pressure is stated in pascals: 1 Pa is a third of the weight of a 300 g/m²
//! fabric, far below what any tool presses with.

/// The trigger: its pressure and the seed of its pattern.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trigger {
    /// The root-mean-square of the out-of-plane pressure, MPa (N/mm²).
    pub pressure_mpa: f64,
    /// The seed of the pattern.
    pub seed: u64,
}

/// The default trigger pressure, MPa (1 Pa).
pub const DEFAULT_TRIGGER_MPA: f64 = 1e-6;

/// The number of plane waves in the pattern.
pub const MODES: usize = 16;

/// The shortest and longest wavelength of the pattern, mm: fabric wrinkles are some 10–50 mm
/// long.
pub const WAVELENGTH_MM: [f64; 2] = [8.0, 60.0];

/// SplitMix64: a small, well-mixed generator, enough for a reproducible pattern.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in [0, 1).
fn uniform(state: &mut u64) -> f64 {
    (splitmix(state) >> 11) as f64 / (1u64 << 53) as f64
}

/// One plane wave of the pattern: wave vector (rad/mm) and phase.
#[derive(Clone, Copy, Debug)]
struct Wave {
    k: [f64; 2],
    phase: f64,
}

impl Trigger {
    fn waves(&self) -> Vec<Wave> {
        let mut state = self.seed;
        let tau = std::f64::consts::TAU;
        (0..MODES)
            .map(|_| {
                let [lo, hi] = WAVELENGTH_MM;
                let wavelength = lo + (hi - lo) * uniform(&mut state);
                let direction = tau * uniform(&mut state);
                let k = tau / wavelength;
                Wave {
                    k: [k * direction.cos(), k * direction.sin()],
                    phase: tau * uniform(&mut state),
                }
            })
            .collect()
    }

    /// The pattern `s` at plan position `(x, y)` (mm): unit root-mean-square over a plane.
    pub fn pattern(&self, x: f64, y: f64) -> f64 {
        pattern_of(&self.waves(), x, y)
    }

    /// The trigger's force along z on each node (N), from the nodes' initial positions and
    /// tributary areas (mm²).
    pub fn forces(&self, nodes: &[[f64; 3]], area: &[f64]) -> Vec<f64> {
        let waves = self.waves();
        nodes
            .iter()
            .zip(area)
            .map(|(p, a)| self.pressure_mpa * a * pattern_of(&waves, p[0], p[1]))
            .collect()
    }
}

fn pattern_of(waves: &[Wave], x: f64, y: f64) -> f64 {
    // Each cosine has mean square 1/2 over a plane, and they are independent.
    let norm = (2.0 / waves.len() as f64).sqrt();
    norm * waves
        .iter()
        .map(|w| (w.k[0] * x + w.k[1] * y + w.phase).cos())
        .sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rms_over(t: &Trigger, half: f64, n: usize) -> f64 {
        let mut s2 = 0.0;
        for i in 0..n {
            for j in 0..n {
                let x = -half + 2.0 * half * (i as f64 + 0.5) / n as f64;
                let y = -half + 2.0 * half * (j as f64 + 0.5) / n as f64;
                s2 += t.pattern(x, y).powi(2);
            }
        }
        (s2 / (n * n) as f64).sqrt()
    }

    #[test]
    fn the_pattern_has_unit_rms_over_a_large_plane() {
        for seed in [1, 2, 3] {
            let t = Trigger {
                pressure_mpa: 1e-6,
                seed,
            };
            let rms = rms_over(&t, 600.0, 400);
            assert!((rms - 1.0).abs() < 0.05, "seed {seed}: rms {rms}");
        }
    }

    #[test]
    fn a_seed_gives_one_pattern_and_two_seeds_two() {
        let a = Trigger {
            pressure_mpa: 1e-6,
            seed: 7,
        };
        let b = Trigger { seed: 8, ..a };
        let p = [3.0, -11.0];
        assert_eq!(a.pattern(p[0], p[1]), a.pattern(p[0], p[1]));
        let differ = (0..20)
            .filter(|i| {
                let x = 5.0 * *i as f64;
                (a.pattern(x, 0.0) - b.pattern(x, 0.0)).abs() > 1e-3
            })
            .count();
        assert!(differ > 15);
    }

    #[test]
    fn forces_are_pressure_times_area_times_pattern() {
        let t = Trigger {
            pressure_mpa: 2e-6,
            seed: 1,
        };
        let nodes = [[0.0, 0.0, 0.0], [10.0, 4.0, 0.0]];
        let f = t.forces(&nodes, &[6.25, 3.0]);
        assert!((f[0] - 2e-6 * 6.25 * t.pattern(0.0, 0.0)).abs() < 1e-18);
        assert!((f[1] - 2e-6 * 3.0 * t.pattern(10.0, 4.0)).abs() < 1e-18);
    }
}
