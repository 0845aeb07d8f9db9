//! In-plane shear of the woven cell (beyond the paper): the shear moment per unit initial
//! area `M(γ) = k1 γ + k3 γ³ + k5 γ⁵` (N·mm/mm² = N/mm, γ the change of the angle between
//! the yarns in radians, positive when it closes), the polynomial of the international
//! woven-fabric benchmark (Cao et al. 2008), and its energy `Ψ(γ) = ∫₀^γ M = k1 γ²/2 +
//! k3 γ⁴/4 + k5 γ⁶/6` per unit initial area.
//!
//! The kinematics: with `fα` the current images of the cell's unit yarn vectors,
//! `cos θ = f1·f2 / (|f1| |f2|)` and `γ = θ0 − θ`. [`shear_kinematics`] gives γ with its
//! gradient and Hessian in `(f1, f2)`; the element chains them to the nodes.

/// The shear law: the polynomial's coefficients `[k1, k3, k5]`, N/mm, and optionally its
/// stiffening past the locking angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShearLaw {
    pub k: [f64; 3],
    pub locking: Option<Locking>,
}

/// Locking as a stiffening (beyond the benchmark's polynomial): past `gamma_rad` the moment
/// gains `k_lock (|γ| − γL)²` (sign of γ), its energy `k_lock (|γ| − γL)³ / 3`. The moment and
/// its slope are continuous at γL; `k_lock` (N·mm/mm² per rad²) is set so that 5° past γL the
/// slope is 20 times the polynomial's slope at γL (at least k1's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Locking {
    pub gamma_rad: f64,
    pub k_lock: f64,
}

impl ShearLaw {
    /// The polynomial law alone.
    pub const fn new(k: [f64; 3]) -> Self {
        ShearLaw { k, locking: None }
    }

    /// The same law stiffening past `locking_deg` (see [`Locking`]).
    pub fn with_locking(mut self, locking_deg: f64) -> Self {
        let gamma = locking_deg.to_radians();
        let slope = self.polynomial_stiffness(gamma).max(self.k[0]).max(1e-6);
        self.locking = Some(Locking {
            gamma_rad: gamma,
            k_lock: 20.0 * slope / (2.0 * 5f64.to_radians()),
        });
        self
    }

    /// How far past locking `g` is (≥ 0), rad, with the lock's stiffness.
    fn past(&self, g: f64) -> (f64, f64) {
        match self.locking {
            Some(l) if g.abs() > l.gamma_rad => (g.abs() - l.gamma_rad, l.k_lock),
            _ => (0.0, 0.0),
        }
    }

    fn polynomial_stiffness(&self, g: f64) -> f64 {
        let g2 = g * g;
        self.k[0] + g2 * (3.0 * self.k[1] + 5.0 * g2 * self.k[2])
    }

    /// The energy per unit initial area at γ, N·mm/mm².
    pub fn energy(&self, g: f64) -> f64 {
        let g2 = g * g;
        let (p, kl) = self.past(g);
        g2 * (self.k[0] / 2.0 + g2 * (self.k[1] / 4.0 + g2 * self.k[2] / 6.0))
            + kl * p * p * p / 3.0
    }

    /// The shear moment per unit initial area `M(γ)`, N·mm/mm².
    pub fn moment(&self, g: f64) -> f64 {
        let g2 = g * g;
        let (p, kl) = self.past(g);
        g * (self.k[0] + g2 * (self.k[1] + g2 * self.k[2])) + g.signum() * kl * p * p
    }

    /// Whether the moment rises from 0 to 90° (finite, k1 ≥ 0, dM/dγ ≥ 0 on a 1° grid): a
    /// law that softens somewhere has no unique answer.
    pub fn rises(&self) -> bool {
        self.k.iter().all(|v| v.is_finite())
            && self.k[0] >= 0.0
            && (0..=90).all(|d| self.stiffness((d as f64).to_radians()) >= 0.0)
    }

    /// `dM/dγ`, N·mm/mm² per radian.
    pub fn stiffness(&self, g: f64) -> f64 {
        let (p, kl) = self.past(g);
        self.polynomial_stiffness(g) + 2.0 * kl * p
    }
}

/// The shear angle at a point and its derivatives in the yarn images `(f1, f2)`.
#[derive(Clone, Copy, Debug, Default)]
pub struct ShearKinematics {
    /// `γ = θ0 − θ`, rad.
    pub gamma: f64,
    /// `∂γ/∂fα`, `[α][m]`.
    pub grad: [[f64; 3]; 2],
    /// `∂²γ/∂fα∂fβ`, `[α][β][m][n]` (only when asked).
    pub hess: [[[[f64; 3]; 3]; 2]; 2],
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// γ of the yarn images `f` against the initial angle `theta0` (rad), with its gradient and,
/// when `hessian`, its Hessian. `sin θ` is kept above 1e-6 (the yarns folded onto each other,
/// far past any locking angle).
pub fn shear_kinematics(f: &[[f64; 3]; 2], theta0: f64, hessian: bool) -> ShearKinematics {
    let n = [dot(f[0], f[0]).sqrt(), dot(f[1], f[1]).sqrt()];
    let mut out = ShearKinematics::default();
    if n[0] <= 0.0 || n[1] <= 0.0 {
        return out;
    }
    let u = [f[0].map(|v| v / n[0]), f[1].map(|v| v / n[1])];
    let c = dot(u[0], u[1]).clamp(-1.0, 1.0);
    let s = (1.0 - c * c).sqrt().max(1e-6);
    out.gamma = theta0 - c.acos();
    // ∂c/∂fα = (u_other − c uα)/|fα|; dγ = dc / sin θ.
    let mut gc = [[0.0; 3]; 2];
    for a in 0..2 {
        let o = 1 - a;
        for m in 0..3 {
            gc[a][m] = (u[o][m] - c * u[a][m]) / n[a];
            out.grad[a][m] = gc[a][m] / s;
        }
    }
    if !hessian {
        return out;
    }
    // ∂²c/∂fα∂fα = −(uα gαᵀ + gα uαᵀ)/|fα| − c (I − uα uαᵀ)/|fα|²;
    // ∂²c/∂f1m∂f2n = (δmn − u1m u1n − u2m u2n + c u1m u2n)/(|f1||f2|).
    // Then ∂²γ = ∂²c / sin θ + (c / sin³θ) ∇c ∇cᵀ.
    let curv = c / (s * s * s);
    for a in 0..2 {
        for b in 0..2 {
            for m in 0..3 {
                for k in 0..3 {
                    let delta = if m == k { 1.0 } else { 0.0 };
                    let hc = if a == b {
                        -(u[a][m] * gc[a][k] + gc[a][m] * u[a][k]) / n[a]
                            - c * (delta - u[a][m] * u[a][k]) / (n[a] * n[a])
                    } else {
                        // [m] along fa, [k] along fb.
                        (delta - u[a][m] * u[a][k] - u[b][m] * u[b][k] + c * u[a][m] * u[b][k])
                            / (n[a] * n[b])
                    };
                    out.hess[a][b][m][k] = hc / s + curv * gc[a][m] * gc[b][k];
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_moment_is_the_energys_derivative_and_the_stiffness_the_moments() {
        let law = ShearLaw::new([0.08, -0.05, 0.2]).with_locking(50.0);
        for g in [-0.9, -0.2, 0.0, 0.3, 0.86, 0.88, 1.1] {
            let h = 1e-6;
            let dm = (law.energy(g + h) - law.energy(g - h)) / (2.0 * h);
            let ds = (law.moment(g + h) - law.moment(g - h)) / (2.0 * h);
            assert!((dm - law.moment(g)).abs() < 1e-8, "{g}");
            assert!((ds - law.stiffness(g)).abs() < 1e-8, "{g}");
        }
    }

    #[test]
    fn gamma_gradient_and_hessian_match_finite_differences() {
        let f = [[1.02, 0.13, -0.04], [0.31, 0.97, 0.08]];
        let theta0 = std::f64::consts::FRAC_PI_2;
        let k = shear_kinematics(&f, theta0, true);
        let h = 1e-6;
        for a in 0..2 {
            for m in 0..3 {
                let (mut fp, mut fm) = (f, f);
                fp[a][m] += h;
                fm[a][m] -= h;
                let (kp, km) = (
                    shear_kinematics(&fp, theta0, false),
                    shear_kinematics(&fm, theta0, false),
                );
                let g = (kp.gamma - km.gamma) / (2.0 * h);
                assert!((g - k.grad[a][m]).abs() < 1e-7, "grad {a}{m}");
                for b in 0..2 {
                    for n in 0..3 {
                        let d = (kp.grad[b][n] - km.grad[b][n]) / (2.0 * h);
                        assert!(
                            (d - k.hess[a][b][m][n]).abs() < 1e-6,
                            "hess {a}{b}{m}{n}: {d} vs {}",
                            k.hess[a][b][m][n]
                        );
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod locking_tests {
    use super::*;

    #[test]
    fn locking_leaves_the_law_below_it_and_stiffens_it_past_it() {
        let plain = ShearLaw::new([0.04, -0.08, 0.08]);
        let locked = plain.with_locking(60.0);
        for d in [0.0, 20.0, 59.9] {
            let g = f64::to_radians(d);
            assert_eq!(plain.moment(g), locked.moment(g));
        }
        let at = 60f64.to_radians();
        let five = 65f64.to_radians();
        // 5° past: the slope is the polynomial's plus 20 × its slope at locking.
        let extra = locked.stiffness(five) - plain.stiffness(five);
        assert!((extra - 20.0 * plain.stiffness(at)).abs() < 1e-9 * extra);
        assert!(locked.moment(five) > plain.moment(five));
    }
}
