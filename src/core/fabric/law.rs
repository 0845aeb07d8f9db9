//! The biaxial woven-cell law of the paper (eqs 1–5) and the linear yarn law beside it.
//!
//! Units: mm, N. Direction 1 is the warp, 2 the weft.
//!
//! The quarter cell: yarn α runs over a half wavelength `L0α/2` and rises to its crown at height
//! `hα`; initially `hα = e0α`. The crowns move by `wα` with `h1 = e01 − w1`, `h2 = e02 + w2`, so the
//! *closure* `s = w1 − w2` is how much the yarns flatten each other at the crossing.
//!
//! Written with `ℓα = sqrt(4 hα² + Lα²)` (the doubled current yarn length, eq 3), `Lα = L0α (1+εα)`
//! and `qα = 1/ℓ0α − 1/ℓα`, the yarn's vertical and horizontal force components are
//!
//! ```text
//!   Vα = Tfα cosθα = 2 Cα hα qα        Tαα = Tfα sinθα = Cα Lα qα      (qα > 0, else both 0)
//! ```
//!
//! and the state `(h1, s)` solves vertical equilibrium `V1 = V2` and the transverse compression
//! law `s = A (1 − exp(−B Fc))`, `Fc = 2 V1` (eqs 2, 5). The cell is conservative: its stored energy
//! is `Σα ½ Cα ℓ0α (ℓα/ℓ0α − 1)² + Φ(s)`, `Φ' = Fc`, minimised over the crimp state, and
//! `∂W/∂εα = L0α Tαα`, hence the symmetric weighted tangent `L01 ∂T11/∂ε2 = L02 ∂T22/∂ε1`.

/// The parameters of a woven cell (eqs 6–7 for the paper's glass plain weave).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellParams {
    /// `L0α`: cell length (wavelength) along each yarn, mm.
    pub l0: [f64; 2],
    /// `e0α`: initial crown height of each yarn, mm.
    pub e0: [f64; 2],
    /// `Cα`: tensile stiffness of each yarn, N.
    pub c: [f64; 2],
    /// `A`: saturation of the closure, mm.
    pub a: f64,
    /// `B`: transverse compliance rate, 1/N.
    pub b: f64,
    /// Undulation variations on (the woven law) or off (the linear yarn law, `T = C max(ε, 0)`).
    pub undulation: bool,
}

impl CellParams {
    /// The cell's mean side, mm: the scale the homogenised law describes.
    pub fn cell_mm(&self) -> f64 {
        0.5 * (self.l0[0] + self.l0[1])
    }

    /// The paper's plain-weave glass fabric (eqs 6–7), undulation on.
    pub const PAPER_GLASS: CellParams = CellParams {
        l0: [4.76, 4.76],
        e0: [0.238, 0.238],
        c: [38000.0, 38000.0],
        a: 0.075,
        b: 0.25,
        undulation: true,
    };
}

/// The crimp state of one cell: the warp crown height `h1` (mm) and the closure `s` (mm).
/// Each cell keeps its own and passes it back in as a warm start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrimpState {
    pub h1: f64,
    pub s: f64,
}

/// What the law returns for one strain pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellResponse {
    /// `Tαα`: tension per yarn, N.
    pub t: [f64; 2],
    /// `∂Tαα/∂εββ`: `dt[α][β]`, N.
    pub dt: [[f64; 2]; 2],
    /// The crimp state reached.
    pub crimp: CrimpState,
    /// Newton iterations the crimp solve took (0 for the linear law or slack yarns).
    pub iterations: u32,
}

impl CellResponse {
    /// Crown displacements `(w1, w2)` in mm, the paper's unknowns.
    pub fn w(&self, law: &CellLaw) -> [f64; 2] {
        let h2 = law.h_total - self.crimp.s - self.crimp.h1;
        [law.p.e0[0] - self.crimp.h1, h2 - law.p.e0[1]]
    }
}

/// A yarn strain within this of zero is an unstrained yarn (the blank's initial state, to the
/// round-off of a length computed from positions): its tangent is the taut slope `C`.
const UNSTRAINED: f64 = 1e-12;

/// A ready-to-evaluate law: the parameters and the constants derived from them.
#[derive(Clone, Copy, Debug)]
pub struct CellLaw {
    pub p: CellParams,
    /// The in-plane shear law (beyond the paper); `None`: the paper's cell, free to shear.
    pub shear: Option<crate::core::fabric::shear::ShearLaw>,
    /// `1/ℓ0α`, the inverse initial doubled yarn length.
    inv_len0: [f64; 2],
    /// `e01 + e02`, mm.
    h_total: f64,
    /// The width of the toe rounding the slack/taut kink, as a yarn strain ([`crate::core::fabric::toe`];
    /// 0: the paper's kink).
    toe: f64,
    /// Each yarn's stiffness in compression as a fraction of `C` (0: the paper's yarns, which
    /// shorten for free). The linear law takes it into its yarn's toe; the woven law adds it
    /// beside the crimp interchange (`CellLaw::cell_compression`).
    compression: [f64; 2],
}

/// One yarn's force components and their partial derivatives at a given `(h, L)`.
#[derive(Clone, Copy, Debug, Default)]
struct Yarn {
    v: f64,
    t: f64,
    v_h: f64,
    v_l: f64,
    t_h: f64,
    t_l: f64,
}

impl CellLaw {
    /// The mean yarn stiffness over the mean cell length, `C̄/L̄0` (N/mm per cell): the
    /// tensile stiffness of one cell, the scale of the contact penalty.
    pub fn stiffness_per_cell(&self) -> f64 {
        let c_mean = 0.5 * (self.p.c[0] + self.p.c[1]);
        let l_mean = 0.5 * (self.p.l0[0] + self.p.l0[1]);
        c_mean / l_mean
    }

    /// The width of the toe rounding the slack/taut kink, as a yarn strain (0: the paper's
    /// kink).
    pub fn toe(&self) -> f64 {
        self.toe
    }

    pub fn new(p: CellParams) -> Self {
        let len0 = |a: usize| (p.l0[a] * p.l0[a] + 4.0 * p.e0[a] * p.e0[a]).sqrt();
        CellLaw {
            p,
            shear: None,
            inv_len0: [1.0 / len0(0), 1.0 / len0(1)],
            h_total: p.e0[0] + p.e0[1],
            toe: 0.0,
            compression: [0.0; 2],
        }
    }

    /// The same cell with yarns that resist compression with the stiffness `fraction · C`
    /// (per yarn; [`crate::core::fabric::toe::phi_compressive`]): in the linear law the yarn's
    /// own tension, in the woven law a term beside the crimp interchange
    /// (`CellLaw::cell_compression`).
    pub fn with_compression(mut self, fraction: [f64; 2]) -> Self {
        self.compression = fraction.map(|f| f.max(0.0));
        self
    }

    /// The same cell with the in-plane shear law `shear` (or none).
    pub fn with_shear(mut self, shear: Option<crate::core::fabric::shear::ShearLaw>) -> Self {
        self.shear = shear;
        self
    }

    /// The same cell with the slack/taut kink rounded over a yarn strain `toe`
    /// ([`crate::core::fabric::toe`]; 0 keeps the paper's kink).
    pub fn with_toe(mut self, toe: f64) -> Self {
        self.toe = toe.max(0.0);
        self
    }

    /// The crimp state before any load.
    pub fn initial_state(&self) -> CrimpState {
        CrimpState {
            h1: self.p.e0[0],
            s: 0.0,
        }
    }

    #[inline]
    fn yarn(&self, a: usize, h: f64, l: f64) -> Yarn {
        let len2 = 4.0 * h * h + l * l;
        let len = len2.sqrt();
        let q = self.inv_len0[a] - 1.0 / len;
        if q <= 0.0 {
            return Yarn::default();
        }
        let c = self.p.c[a];
        if self.toe > 0.0 {
            return self.yarn_on_toe(a, h, l, len);
        }
        let il3 = 1.0 / (len2 * len);
        Yarn {
            v: 2.0 * c * h * q,
            t: c * l * q,
            v_h: 2.0 * c * (q + 4.0 * h * h * il3),
            v_l: 2.0 * c * h * l * il3,
            t_h: 4.0 * c * l * h * il3,
            t_l: c * (q + l * l * il3),
        }
    }

    /// [`CellLaw::yarn`] with the kink rounded: the yarn force `c φ(s)` at its strain
    /// `s = len/ℓ0 − 1`, written as `q = φ/len` in place of `1/ℓ0 − 1/len`.
    fn yarn_on_toe(&self, a: usize, h: f64, l: f64, len: f64) -> Yarn {
        let c = self.p.c[a];
        let (phi, dphi) = crate::core::fabric::toe::phi(len * self.inv_len0[a] - 1.0, self.toe);
        let q = phi / len;
        // dq/dlen, and through len = √(4h² + l²) its partials in h and l.
        let dq = (dphi * self.inv_len0[a] - q) / len;
        let (q_h, q_l) = (dq * 4.0 * h / len, dq * l / len);
        Yarn {
            v: 2.0 * c * h * q,
            t: c * l * q,
            v_h: 2.0 * c * (q + h * q_h),
            v_l: 2.0 * c * h * q_l,
            t_h: c * l * q_h,
            t_l: c * (q + l * q_l),
        }
    }

    /// Crown height below which yarn α is slack at horizontal length `l` (−∞ if always taut).
    fn slack_height(&self, a: usize, l: f64) -> f64 {
        let len0 = 1.0 / self.inv_len0[a];
        let d = len0 * len0 - l * l;
        if d <= 0.0 {
            f64::NEG_INFINITY
        } else {
            0.5 * d.sqrt()
        }
    }

    /// Tensions and tangent for the strains `eps` (along warp and weft), warm-started from `state`.
    pub fn evaluate(&self, eps: [f64; 2], state: CrimpState) -> CellResponse {
        if !self.p.undulation {
            return self.evaluate_linear(eps);
        }
        self.with_cell_compression(eps, self.evaluate_woven(eps, state))
    }

    /// `r` with the woven law's compressive branch added (`CellLaw::cell_compression`).
    fn with_cell_compression(&self, eps: [f64; 2], mut r: CellResponse) -> CellResponse {
        for a in 0..2 {
            let (t, dt) = self.cell_compression(a, eps[a]);
            r.t[a] += t;
            r.dt[a][a] += dt;
        }
        r
    }

    /// The woven law's compressive branch, yarn `a` at the cell's strain `eps` along it: the
    /// tension (N, negative in compression) and its slope that the linear law's compressive toe
    /// adds to its plain toe, `C (φc(ε) − φ(ε))` ([`crate::core::fabric::toe::phi_compressive`]):
    /// `r C ε` below zero strain, fading to a constant `r C w/2` over the toe. So the woven cell
    /// with compression takes, beside its crimp interchange, what the linear law takes: a yarn
    /// shortened in the cell's plane resists with the slope `r C`, continuous in value and slope
    /// across zero and the toe. It stands beside the crimp solve, not in the undulated yarn's
    /// length: there a compressive yarn makes the cell's energy non-convex in its crown height
    /// (`Φ(s(h))` with `s` convex and `Φ` falling) past about `4h²/ℓ0L` of compression, 1 % for
    /// the paper's fabric, and the crimp solve would have no unique state. Where the yarns are
    /// stretched the crimp interchange is untouched.
    fn cell_compression(&self, a: usize, eps: f64) -> (f64, f64) {
        let r = self.compression[a];
        if r == 0.0 {
            return (0.0, 0.0);
        }
        let (pc, dpc) = crate::core::fabric::toe::phi_compressive(eps, self.toe, r);
        let (p, dp) = crate::core::fabric::toe::phi(eps, self.toe);
        (self.p.c[a] * (pc - p), self.p.c[a] * (dpc - dp))
    }

    /// The energy of `CellLaw::cell_compression` over a cell, N·mm.
    fn cell_compression_energy(&self, a: usize, eps: f64) -> f64 {
        let r = self.compression[a];
        if r == 0.0 {
            return 0.0;
        }
        let ec = crate::core::fabric::toe::energy_compressive(eps, self.toe, r);
        let e = crate::core::fabric::toe::energy(eps, self.toe);
        self.p.c[a] * self.p.l0[a] * (ec - e)
    }

    /// [`CellLaw::evaluate`] of the woven law without its compressive branch.
    fn evaluate_woven(&self, eps: [f64; 2], state: CrimpState) -> CellResponse {
        let l = [self.p.l0[0] * (1.0 + eps[0]), self.p.l0[1] * (1.0 + eps[1])];
        let hh = self.h_total;
        // Both yarns slack somewhere in the admissible range: no tension, the crimp stays put.
        let h1_slack = self.slack_height(0, l[0]);
        let h1_min_for_2_slack = hh - self.slack_height(1, l[1]);
        // (With a tolerance of 1e-12 of the crimp height: round-off at zero strain must not make
        // a yarn "taut" by 1e-16 and send the solve to its slow fallback.)
        if h1_min_for_2_slack <= h1_slack + 1e-12 * hh {
            let (lo, hi) = (h1_min_for_2_slack.max(0.0), h1_slack.min(hh));
            // Within the tolerance the bounds may cross by round-off: take their middle then.
            let h1 = if lo <= hi {
                self.p.e0[0].clamp(lo, hi)
            } else {
                0.5 * (lo + hi)
            };
            return CellResponse {
                t: [0.0, 0.0],
                dt: [[0.0; 2]; 2],
                crimp: CrimpState { h1, s: 0.0 },
                iterations: 0,
            };
        }
        let (crimp, iterations) = self
            .newton_2x2(l, state)
            .unwrap_or_else(|| self.nested_newton(l, state));
        self.respond(l, crimp, iterations)
    }

    /// The same answer as [`CellLaw::evaluate`] by the slow nested bracketed solve only (no
    /// Newton, no warm start): a reference to check the fast path against.
    pub fn evaluate_bracketed(&self, eps: [f64; 2]) -> CellResponse {
        if !self.p.undulation {
            return self.evaluate_linear(eps);
        }
        let l = [self.p.l0[0] * (1.0 + eps[0]), self.p.l0[1] * (1.0 + eps[1])];
        if self.slack_height(0, l[0]) + 1e-12 * self.h_total
            >= self.h_total - self.slack_height(1, l[1])
        {
            return self.evaluate(eps, self.initial_state());
        }
        let x = self.bracketed(l);
        self.with_cell_compression(eps, self.respond(l, x, 0))
    }

    /// Residuals `R1 = V1 − V2`, `R2 = s − A(1 − e^{−2B V1})` and their Jacobian at `(h1, s)`.
    #[inline]
    fn system(&self, l: [f64; 2], x: CrimpState) -> ([f64; 2], [[f64; 2]; 2], Yarn, Yarn, f64) {
        let y1 = self.yarn(0, x.h1, l[0]);
        let y2 = self.yarn(1, self.h_total - x.s - x.h1, l[1]);
        let (a, b) = (self.p.a, self.p.b);
        let e = (-2.0 * b * y1.v).exp();
        let r = [y1.v - y2.v, x.s - a * (1.0 - e)];
        let j = [[y1.v_h + y2.v_h, y2.v_h], [-2.0 * a * b * e * y1.v_h, 1.0]];
        (r, j, y1, y2, e)
    }

    /// The fast path: plain Newton on the 2×2 system from the warm start, projected on the
    /// admissible set, at most 8 iterations; accepted only when both residuals are at round-off
    /// level (the cell's energy is convex, so that point is the solution). `None` otherwise.
    fn newton_2x2(&self, l: [f64; 2], start: CrimpState) -> Option<(CrimpState, u32)> {
        let hh = self.h_total;
        let a = self.p.a;
        let mut x = CrimpState {
            s: start.s.clamp(0.0, a),
            h1: 0.0,
        };
        x.h1 = start.h1.clamp(0.0, hh - x.s);
        for it in 0..8 {
            let (r, j, y1, y2, _) = self.system(l, x);
            let _ = (&y1, &y2);
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            if !(det.is_finite() && det > 0.0) {
                return None;
            }
            let dh = -(r[0] * j[1][1] - j[0][1] * r[1]) / det;
            let ds = -(j[0][0] * r[1] - j[1][0] * r[0]) / det;
            x.s = (x.s + ds).clamp(0.0, a);
            x.h1 = (x.h1 + dh).clamp(0.0, hh - x.s);
            // Converged once a full Newton correction is below 1e-12 of the heights (the
            // residuals themselves bottom out at the round-off of V = 2Ch(1/ℓ0 − 1/ℓ)); with
            // quadratic convergence the error left is far below that.
            if dh.abs() <= 1e-12 * hh && ds.abs() <= 1e-12 * a.max(1e-300) && it > 0 {
                return Some((x, it + 1));
            }
        }
        None
    }

    /// Vertical equilibrium for a given closure `s`: `V1(h1) = V2(H − s − h1)`, nondecreasing in
    /// `h1` on `[0, H − s]`; Newton safeguarded by that bracket, from `guess`.
    fn solve_h1(&self, l: [f64; 2], s: f64, guess: f64, v_tol: f64) -> (f64, u32) {
        let hh = self.h_total;
        let (mut lo, mut hi) = (0.0, hh - s);
        let mut h = guess.clamp(lo, hi);
        for it in 1..=100 {
            let y1 = self.yarn(0, h, l[0]);
            let y2 = self.yarn(1, hh - s - h, l[1]);
            let f = y1.v - y2.v;
            if f.abs() <= v_tol + 1e-14 * (y1.v + y2.v) {
                return (h, it);
            }
            if f > 0.0 {
                hi = h;
            } else {
                lo = h;
            }
            let df = y1.v_h + y2.v_h;
            let mut next = if df > 0.0 { h - f / df } else { f64::NAN };
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - h).abs() <= 1e-13 * hh || hi - lo <= 1e-15 * hh {
                return (next, it);
            }
            h = next;
        }
        (h, 100)
    }

    /// The crimp state by nested safeguarded Newton solves, warm-started from `start`: the
    /// closure equation `g(s) = s − A(1 − e^{−2B V1}) = 0` is increasing in `s` on `[0, A]`
    /// (`g' = 1 + 2ABe V1h V2h/(V1h + V2h) ≥ 1`), and for each `s` the vertical equilibrium is
    /// solved in `h1` (see [`CellLaw::solve_h1`]). Brackets make it unable to fail; Newton makes
    /// it converge in a few steps from a warm start.
    fn nested_newton(&self, l: [f64; 2], start: CrimpState) -> (CrimpState, u32) {
        let hh = self.h_total;
        let (a, b) = (self.p.a, self.p.b);
        let v_tol = 1e-300;
        let mut h1 = start.h1;
        let mut iterations = 0;
        let eval = |s: f64, h_guess: f64, its: &mut u32| -> (f64, f64, f64) {
            let (h, n) = self.solve_h1(l, s, h_guess, v_tol);
            *its += n;
            let y1 = self.yarn(0, h, l[0]);
            let y2 = self.yarn(1, hh - s - h, l[1]);
            let e = (-2.0 * b * y1.v).exp();
            let g = s - a * (1.0 - e);
            let sum = y1.v_h + y2.v_h;
            let dg = if sum > 0.0 {
                1.0 + 2.0 * a * b * e * y1.v_h * y2.v_h / sum
            } else {
                1.0
            };
            (h, g, dg)
        };
        let (mut lo, mut hi) = (0.0, a);
        let mut s = start.s.clamp(lo, hi);
        for _ in 0..100 {
            let (h, g, dg) = eval(s, h1, &mut iterations);
            h1 = h;
            if g.abs() <= 1e-15 * a || a == 0.0 {
                break;
            }
            if g > 0.0 {
                hi = s;
            } else {
                lo = s;
            }
            if g >= 0.0 && s == 0.0 {
                break; // no compression: the closure stays 0
            }
            // Newton, kept strictly inside the bracket (a step onto an end could cycle between
            // both ends of a kink), else bisection.
            let mut next = s - g / dg;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - s).abs() <= 1e-13 * a || hi - lo <= 1e-15 * a {
                s = next;
                let (h, _, _) = eval(s, h1, &mut iterations);
                h1 = h;
                break;
            }
            s = next;
        }
        (CrimpState { h1, s }, iterations)
    }

    /// The robust fallback: nested bracketed solves, monotone in `h1` for a given closure, then
    /// monotone in the closure.
    fn bracketed(&self, l: [f64; 2]) -> CrimpState {
        let hh = self.h_total;
        let h1_of = |s: f64| -> f64 {
            // V1(h1) − V2(H − s − h1) is nondecreasing in h1 on [0, H − s].
            let (mut lo, mut hi) = (0.0, hh - s);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                let r = self.yarn(0, mid, l[0]).v - self.yarn(1, hh - s - mid, l[1]).v;
                if r > 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
                if hi - lo <= 1e-16 * hh {
                    break;
                }
            }
            0.5 * (lo + hi)
        };
        let g = |s: f64| -> f64 {
            let h1 = h1_of(s);
            s - self.p.a * (1.0 - (-2.0 * self.p.b * self.yarn(0, h1, l[0]).v).exp())
        };
        if g(0.0) >= 0.0 {
            return CrimpState {
                h1: h1_of(0.0),
                s: 0.0,
            };
        }
        let (mut lo, mut hi) = (0.0, self.p.a);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if g(mid) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
            if hi - lo <= 1e-16 * self.p.a {
                break;
            }
        }
        let s = 0.5 * (lo + hi);
        CrimpState { h1: h1_of(s), s }
    }

    /// Tensions and the implicit-differentiation tangent at a solved crimp state.
    fn respond(&self, l: [f64; 2], x: CrimpState, iterations: u32) -> CellResponse {
        let (_, j, y1, y2, e) = self.system(l, x);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        // ∂R/∂L columns: R1 = V1(L1) − V2(L2), R2 = s − A(1 − e^{−2B V1(L1)}).
        let drdl = [
            [y1.v_l, -y2.v_l],
            [-2.0 * self.p.a * self.p.b * e * y1.v_l, 0.0],
        ];
        let mut dt = [[0.0; 2]; 2];
        for beta in 0..2 {
            let (r1, r2) = (-drdl[0][beta], -drdl[1][beta]);
            let (dh, ds) = if det > 0.0 {
                (
                    (r1 * j[1][1] - j[0][1] * r2) / det,
                    (j[0][0] * r2 - j[1][0] * r1) / det,
                )
            } else {
                (0.0, 0.0)
            };
            let d1 = if beta == 0 { y1.t_l } else { 0.0 } + y1.t_h * dh;
            let d2 = if beta == 1 { y2.t_l } else { 0.0 } - y2.t_h * (dh + ds);
            dt[0][beta] = d1 * self.p.l0[beta];
            dt[1][beta] = d2 * self.p.l0[beta];
        }
        CellResponse {
            t: [y1.t, y2.t],
            dt,
            crimp: x,
            iterations,
        }
    }

    /// The linear yarn law, `Tαα = Cα max(εα, 0)` (undulation off).
    fn evaluate_linear(&self, eps: [f64; 2]) -> CellResponse {
        let mut r = CellResponse {
            t: [0.0; 2],
            dt: [[0.0; 2]; 2],
            crimp: self.initial_state(),
            iterations: 0,
        };
        for a in 0..2 {
            // At exactly zero strain the taut side's slope is the tangent: an unstrained yarn
            // (the initial state) resists stretching, and the solver must see it.
            if self.compression[a] > 0.0 {
                let rc = self.compression[a];
                let (phi, dphi) = crate::core::fabric::toe::phi_compressive(eps[a], self.toe, rc);
                r.t[a] = self.p.c[a] * phi;
                r.dt[a][a] = self.p.c[a] * dphi;
            } else if self.toe > 0.0 {
                let (phi, dphi) = crate::core::fabric::toe::phi(eps[a], self.toe);
                r.t[a] = self.p.c[a] * phi;
                // The same for an unstrained yarn on the toe, whose own slope there is zero:
                // the taut one. Only the tangent changes, so only where Newton goes, not where
                // it ends (the grid's 81 designs: 15,525 → 15,232 iterations at standard, their
                // figures unchanged, 2026-12-06).
                let slope = if eps[a].abs() <= UNSTRAINED {
                    1.0
                } else {
                    dphi
                };
                r.dt[a][a] = self.p.c[a] * slope;
            } else if eps[a] >= 0.0 {
                r.t[a] = self.p.c[a] * eps[a];
                r.dt[a][a] = self.p.c[a];
            }
        }
        r
    }

    /// Yarn α's energy over length `len0` at strain `s`, N·mm: `C len0 max(s, 0)²/2`, or on
    /// the toe `C len0 Φ(s)` ([`crate::core::fabric::toe::energy`]).
    fn yarn_energy(&self, a: usize, len0: f64, s: f64) -> f64 {
        if self.compression[a] > 0.0 {
            let rc = self.compression[a];
            self.p.c[a] * len0 * crate::core::fabric::toe::energy_compressive(s, self.toe, rc)
        } else if self.toe > 0.0 {
            self.p.c[a] * len0 * crate::core::fabric::toe::energy(s, self.toe)
        } else {
            0.5 * self.p.c[a] * len0 * s.max(0.0).powi(2)
        }
    }

    /// Stored energy of one cell at a solved state (N·mm); `∂W/∂εα = L0α Tαα`.
    pub fn energy(&self, eps: [f64; 2], state: CrimpState) -> f64 {
        if !self.p.undulation {
            return (0..2)
                .map(|a| self.yarn_energy(a, self.p.l0[a], eps[a]))
                .sum();
        }
        let l = [self.p.l0[0] * (1.0 + eps[0]), self.p.l0[1] * (1.0 + eps[1])];
        let h = [state.h1, self.h_total - state.s - state.h1];
        let mut w = 0.0;
        for a in 0..2 {
            let len = (4.0 * h[a] * h[a] + l[a] * l[a]).sqrt();
            let strain = len * self.inv_len0[a] - 1.0;
            if self.toe > 0.0 {
                // The undulated yarn's own toe; its compression is the cell's, added below.
                let len0 = 1.0 / self.inv_len0[a];
                w += self.p.c[a] * len0 * crate::core::fabric::toe::energy(strain, self.toe);
            } else {
                let strain = strain.max(0.0);
                w += 0.5 * self.p.c[a] / self.inv_len0[a] * strain * strain;
            }
        }
        w += (0..2)
            .map(|a| self.cell_compression_energy(a, eps[a]))
            .sum::<f64>();
        // Φ(s) = ∫0^s −ln(1 − t/A)/B dt.
        let (a, b, s) = (self.p.a, self.p.b, state.s);
        if s >= a {
            w += a / b; // the limit of (A − s) ln(1 − s/A) is 0
        } else if s > 0.0 {
            w += ((a - s) * (1.0 - s / a).ln() + s) / b;
        }
        w
    }
}

#[cfg(test)]
#[path = "law_checks.rs"]
mod checks;
