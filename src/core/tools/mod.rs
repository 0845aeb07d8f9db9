//! Rigid analytic tools: signed distance, outward normal (its gradient) and curvature (the
//! Hessian of the distance), smooth (C1) everywhere the fabric can touch.
//!
//! Frame: the blank lies initially in the plane z = 0 on the die face; the punch comes from above
//! and moves down (−z) by the stroke; the die's material is below z = 0 outside its opening.
//!
//! ```text
//!            punch (side a, plan corner radius r, nose radius rp)
//!          ┌──────────┐
//!          │          │            ↓ stroke
//!          ╰──────────╯
//!   ───────╮  blank   ╭───────  die face z = 0 (holder presses the flange here)
//!          │          │          opening a + 2·clearance, corner r + clearance, entry radius rm
//! ```

pub mod capped;
mod closed;
pub mod double_dome;
pub mod flange;
pub mod intersect;
pub mod mesh_tool;
pub mod nearest;
pub mod sampled;
pub mod scale;
pub mod shells;
pub mod surface;
pub mod tessellate;
pub mod tooling;

/// A point's signed distance to a tool surface (negative inside the tool) and its gradient
/// (the outward unit normal at the nearest surface point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distance {
    pub d: f64,
    pub n: [f64; 3],
}

/// Signed distance in the plane, with its gradient.
#[derive(Clone, Copy, Debug)]
struct Plan {
    d: f64,
    g: [f64; 2],
}

/// A rounded rectangle centred at the origin: half sides `hx, hy`, corner radius `r`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoundedRect {
    pub hx: f64,
    pub hy: f64,
    pub r: f64,
}

impl RoundedRect {
    /// The signed distance at `(x, y)` for a corner radius `r` (which may differ from `self.r`),
    /// its gradient and its derivative with respect to `r`.
    fn plan_with_radius(&self, x: f64, y: f64, r: f64) -> (Plan, f64) {
        let (sx, sy) = (sign(x), sign(y));
        let qx = x.abs() - (self.hx - r);
        let qy = y.abs() - (self.hy - r);
        if qx > 0.0 && qy > 0.0 {
            let l = (qx * qx + qy * qy).sqrt();
            return (
                Plan {
                    d: l - r,
                    g: [sx * qx / l, sy * qy / l],
                },
                (qx + qy) / l - 1.0,
            );
        }
        let plan = if qx >= qy {
            Plan {
                d: qx - r,
                g: [sx, 0.0],
            }
        } else {
            Plan {
                d: qy - r,
                g: [0.0, sy],
            }
        };
        (plan, 0.0)
    }

    fn plan(&self, x: f64, y: f64) -> Plan {
        self.plan_with_radius(x, y, self.r).0
    }
}

/// An ellipse centred at the origin with semi-axes `ax, ay`, offset outward by `offset`: the
/// exact signed distance (see `ellipse_distance`; a circle directly).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OffsetEllipse {
    pub ax: f64,
    pub ay: f64,
    pub offset: f64,
}

impl OffsetEllipse {
    fn plan(&self, x: f64, y: f64) -> Plan {
        if self.ax == self.ay {
            // A circle: the distance to its centre less the radius.
            let r = (x * x + y * y).sqrt();
            let g = if r > 0.0 { [x / r, y / r] } else { [1.0, 0.0] };
            return Plan {
                d: r - self.ax - self.offset,
                g,
            };
        }
        let (d, g) = ellipse_distance(self.ax, self.ay, x, y);
        Plan {
            d: d - self.offset,
            g,
        }
    }
}

fn sign(v: f64) -> f64 {
    if v < 0.0 { -1.0 } else { 1.0 }
}

/// Signed distance from `(x, y)` to the ellipse `x²/a² + y²/b² = 1` and its gradient.
///
/// The nearest point of a point `q` in the first quadrant is `xᵢ = aᵢ² qᵢ/(aᵢ² + t)` for the
/// root `t` of `F(t) = Σ (aᵢ qᵢ/(aᵢ² + t))² − 1`, which is decreasing and convex where it
/// matters: Newton from a point left of the root climbs to it monotonically (Eberly, "Distance
/// from a point to an ellipse"; no trigonometry). On the major axis inside the evolute the
/// nearest point is off the axis and has a closed form.
fn ellipse_distance(a: f64, b: f64, x: f64, y: f64) -> (f64, [f64; 2]) {
    // Major axis first.
    let swap = a < b;
    let (e0, e1) = if swap { (b, a) } else { (a, b) };
    let (y0, y1) = if swap {
        (y.abs(), x.abs())
    } else {
        (x.abs(), y.abs())
    };
    let (x0, x1) = if y1 > 0.0 && y0 > 0.0 {
        // In σ = 1 + t/e1² (σ, not t/e1², keeps its digits near the major axis, where t/e1² is
        // near −1): F(σ) = (r z0/(σ − 1 + r))² + (z1/σ)² − 1, r = (e0/e1)², from σ = z1.
        let (z0, z1) = (y0 / e0, y1 / e1);
        let r = (e0 / e1).powi(2);
        let f = |sigma: f64| {
            let (u, v) = (r * z0 / (sigma - 1.0 + r), z1 / sigma);
            let value = u * u + v * v - 1.0;
            let slope = -2.0 * (u * u / (sigma - 1.0 + r) + v * v / sigma);
            (value, slope)
        };
        let mut sigma = z1;
        for _ in 0..64 {
            let (value, slope) = f(sigma);
            if value <= 0.0 || slope >= 0.0 {
                break;
            }
            let next = sigma - value / slope;
            if next - sigma <= 1e-15 * sigma.abs().max(1e-300) {
                sigma = next;
                break;
            }
            sigma = next;
        }
        (r * y0 / (sigma - 1.0 + r), y1 / sigma)
    } else if y1 > 0.0 {
        (0.0, e1)
    } else {
        let (numer, denom) = (e0 * y0, e0 * e0 - e1 * e1);
        if numer < denom {
            let c = numer / denom;
            (e0 * c, e1 * (1.0 - c * c).max(0.0).sqrt())
        } else {
            (e0, 0.0)
        }
    };
    let dist = ((y0 - x0).powi(2) + (y1 - x1).powi(2)).sqrt();
    let inside = (y0 / e0).powi(2) + (y1 / e1).powi(2) < 1.0;
    // Outward normal of the ellipse at the nearest point.
    let (gx, gy) = (x0 / (e0 * e0), x1 / (e1 * e1));
    let l = (gx * gx + gy * gy).sqrt();
    let (n0, n1) = (gx / l, gy / l);
    let (nx, ny) = if swap { (n1, n0) } else { (n0, n1) };
    let d = if inside { -dist } else { dist };
    (d, [sign(x) * nx, sign(y) * ny])
}

/// The rounded intersection of `{f1 ≤ 0}` and `{f2 ≤ 0}` whose edge is rounded with radius
/// `rho`: exact when f1, f2 are distances to orthogonal faces.
fn rounded_intersection(f1: f64, g1: [f64; 3], f2: f64, g2: [f64; 3], rho: f64) -> Distance {
    let (u, v) = (f1 + rho, f2 + rho);
    if u > 0.0 && v > 0.0 {
        let l = (u * u + v * v).sqrt();
        let n = [
            (u * g1[0] + v * g2[0]) / l,
            (u * g1[1] + v * g2[1]) / l,
            (u * g1[2] + v * g2[2]) / l,
        ];
        Distance { d: l - rho, n }
    } else if u >= v {
        Distance { d: f1, n: g1 }
    } else {
        Distance { d: f2, n: g2 }
    }
}

/// The plan shape of a punch or of a die opening.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlanShape {
    RoundedRect(RoundedRect),
    Ellipse(OffsetEllipse),
}

impl PlanShape {
    fn plan(&self, x: f64, y: f64) -> Plan {
        match self {
            PlanShape::RoundedRect(r) => r.plan(x, y),
            PlanShape::Ellipse(e) => e.plan(x, y),
        }
    }
}

/// A rigid tool.
#[derive(Clone, Debug, PartialEq)]
pub enum Tool {
    /// A flat-nosed punch: plan shape extruded upward from its nose at `z = tip`, the nose edge
    /// rounded with radius `nose_radius`.
    FlatPunch {
        plan: PlanShape,
        nose_radius: f64,
        tip: f64,
    },
    /// An ellipsoidal punch of semi-axes `[ax, ay, az]`, lowest point at `z = tip`.
    EllipsoidPunch { axes: [f64; 3], tip: f64 },
    /// A die: material below `z = 0` outside the opening, the entry edge rounded with
    /// `entry_radius`.
    Die {
        opening: PlanShape,
        entry_radius: f64,
    },
    /// A tool from a triangle surface (a punch's lowest point at `z = tip`; a die in place).
    Mesh {
        shape: std::sync::Arc<mesh_tool::MeshTool>,
        tip: f64,
    },
}

impl Tool {
    /// A square (or rectangular) punch of sides `[ax, ay]`, plan corner radius `r`, nose radius
    /// `rp`, tip at `z = tip`.
    pub fn box_punch(side: [f64; 2], r: f64, rp: f64, tip: f64) -> Tool {
        Tool::FlatPunch {
            plan: PlanShape::RoundedRect(RoundedRect {
                hx: 0.5 * side[0],
                hy: 0.5 * side[1],
                r,
            }),
            nose_radius: rp,
            tip,
        }
    }

    /// The die of a box punch: opening `side + 2·clearance`, corner radius `r + clearance`,
    /// entry radius `rm`.
    pub fn box_die(side: [f64; 2], r: f64, clearance: f64, rm: f64) -> Tool {
        Tool::Die {
            opening: PlanShape::RoundedRect(RoundedRect {
                hx: 0.5 * side[0] + clearance,
                hy: 0.5 * side[1] + clearance,
                r: r + clearance,
            }),
            entry_radius: rm,
        }
    }

    /// A die with an elliptical opening: the ellipse of semi-axes `[ax, ay]` offset by the
    /// clearance (a circle when `ax = ay`).
    pub fn elliptic_die(axes: [f64; 2], clearance: f64, rm: f64) -> Tool {
        Tool::Die {
            opening: PlanShape::Ellipse(OffsetEllipse {
                ax: axes[0],
                ay: axes[1],
                offset: clearance,
            }),
            entry_radius: rm,
        }
    }

    /// The same tool moved to its position at a punch tip height (dies do not move).
    pub fn at_tip(&self, z: f64) -> Tool {
        match *self {
            Tool::FlatPunch {
                plan, nose_radius, ..
            } => Tool::FlatPunch {
                plan,
                nose_radius,
                tip: z,
            },
            Tool::EllipsoidPunch { axes, .. } => Tool::EllipsoidPunch { axes, tip: z },
            Tool::Mesh { ref shape, .. } if shape.role == mesh_tool::Role::Punch => Tool::Mesh {
                shape: shape.clone(),
                tip: z,
            },
            ref die => die.clone(),
        }
    }

    /// For a die: the signed plan distance of `(x, y)` to its opening (positive outside, on the
    /// face), its gradient in the plane, and the entry radius.
    pub fn opening_distance(&self, x: f64, y: f64) -> Option<(f64, [f64; 2], f64)> {
        match self {
            Tool::Die {
                opening,
                entry_radius,
            } => {
                let pl = opening.plan(x, y);
                Some((pl.d, pl.g, *entry_radius))
            }
            // The flange's signed distance starts where the face does: no entry radius to add.
            Tool::Mesh { shape, .. } => shape.flange.as_ref().map(|f| {
                let (d, g) = f.distance(x, y);
                (d, g, 0.0)
            }),
            _ => None,
        }
    }

    pub fn is_punch(&self) -> bool {
        match self {
            Tool::Die { .. } => false,
            Tool::Mesh { shape, .. } => shape.role == mesh_tool::Role::Punch,
            _ => true,
        }
    }

    /// Signed distance and outward normal at `p`.
    pub fn distance(&self, p: [f64; 3]) -> Distance {
        match *self {
            Tool::FlatPunch {
                plan,
                nose_radius,
                tip,
            } => {
                let (d, g) = punch_plan(&plan, nose_radius, tip, p);
                // Region {plan ≤ 0} ∩ {z ≥ tip}: f2 = tip − z.
                rounded_intersection(d, g, tip - p[2], [0.0, 0.0, -1.0], nose_radius)
            }
            Tool::Die {
                opening,
                entry_radius,
            } => {
                let pl = opening.plan(p[0], p[1]);
                // Region {outside the opening} ∩ {z ≤ 0}.
                rounded_intersection(
                    -pl.d,
                    [-pl.g[0], -pl.g[1], 0.0],
                    p[2],
                    [0.0, 0.0, 1.0],
                    entry_radius,
                )
            }
            Tool::EllipsoidPunch { axes, tip } => {
                let c = [0.0, 0.0, tip + axes[2]];
                ellipsoid_distance(axes, [p[0] - c[0], p[1] - c[1], p[2] - c[2]])
            }
            Tool::Mesh { ref shape, tip } => {
                let e = shape.distance.evaluate([p[0], p[1], p[2] - tip], false);
                Distance { d: e.d, n: e.n }
            }
        }
    }

    /// Whether the nearest surface to `p`, and to every point within `margin` of it, is the
    /// flat face `z = tip` of a punch or `z = 0` of a die (whose curvature is zero).
    fn on_flat_face(&self, p: [f64; 3], margin: f64) -> bool {
        let (u, v) = match *self {
            Tool::FlatPunch {
                plan,
                nose_radius,
                tip,
            } => (
                punch_plan(&plan, nose_radius, tip, p).0 + nose_radius,
                tip - p[2] + nose_radius,
            ),
            Tool::Die {
                opening,
                entry_radius,
            } => (
                -opening.plan(p[0], p[1]).d + entry_radius,
                p[2] + entry_radius,
            ),
            Tool::EllipsoidPunch { .. } | Tool::Mesh { .. } => return false,
        };
        // The face's branch of the rounded intersection: off the rounded edge (u ≤ 0) and nearer
        // the face than the side (v > u), each with room to spare.
        u <= -margin && v > u + margin
    }

    /// The largest principal curvature (1/mm) of the surface at `p`: the larger root of
    /// `k² − tr k + (tr² − |H|²)/2` for [`Tool::curvature`]'s `H`, whose third eigenvalue (along
    /// the normal) is 0. 0 on a flat face.
    pub fn largest_curvature(&self, p: [f64; 3], scale: f64) -> f64 {
        let h = self.curvature(p, scale);
        let tr = h[0][0] + h[1][1] + h[2][2];
        let f2: f64 = h.iter().flatten().map(|v| v * v).sum();
        0.5 * (tr.abs() + (2.0 * f2 - tr * tr).max(0.0).sqrt())
    }

    /// The Hessian of the signed distance (the curvature of the surface, `∂n/∂x`) at `p`, by
    /// central differences of the analytic normal (zero on a flat face).
    pub fn curvature(&self, p: [f64; 3], scale: f64) -> [[f64; 3]; 3] {
        if let Tool::Mesh { shape, tip } = self {
            // The interpolant's own Hessian.
            let e = shape.distance.evaluate([p[0], p[1], p[2] - tip], true);
            return e.hessian.unwrap_or([[0.0; 3]; 3]);
        }
        let h = 1e-5 * scale.max(1e-3);
        if self.on_flat_face(p, 10.0 * h) {
            return [[0.0; 3]; 3];
        }
        let mut hess = [[0.0; 3]; 3];
        for j in 0..3 {
            let mut pp = p;
            let mut pm = p;
            pp[j] += h;
            pm[j] -= h;
            let (np, nm) = (self.distance(pp).n, self.distance(pm).n);
            for i in 0..3 {
                hess[i][j] = (np[i] - nm[i]) / (2.0 * h);
            }
        }
        for i in 0..3 {
            for j in 0..i {
                let s = 0.5 * (hess[i][j] + hess[j][i]);
                hess[i][j] = s;
                hess[j][i] = s;
            }
        }
        hess
    }
}

/// The plan field of a flat punch at `p` and its 3D gradient.
///
/// A nose ball of radius `rp` cannot roll around a plan corner of smaller radius `r` without
/// reaching the corner arc's centre, where the plan distance is singular. As a tool maker's
/// variable-radius corner blend does, the plan corner radius is `r` above the nose and grows
/// smoothly (C1 in height) to `1.05 rp` at the tip when `r < 1.05 rp`; everywhere else the field
/// is the exact distance.
fn punch_plan(plan: &PlanShape, rp: f64, tip: f64, p: [f64; 3]) -> (f64, [f64; 3]) {
    match plan {
        PlanShape::RoundedRect(rect) if rect.r < 1.05 * rp => {
            let t = ((tip + rp - p[2]) / rp).clamp(0.0, 1.0);
            let s = t * t * (3.0 - 2.0 * t);
            let ds_dz = if t > 0.0 && t < 1.0 {
                -6.0 * t * (1.0 - t) / rp
            } else {
                0.0
            };
            let r_top = rect.r;
            let r_tip = 1.05 * rp;
            let r = r_top + (r_tip - r_top) * s;
            let (pl, dd_dr) = rect.plan_with_radius(p[0], p[1], r);
            (pl.d, [pl.g[0], pl.g[1], dd_dr * (r_tip - r_top) * ds_dz])
        }
        _ => {
            let pl = plan.plan(p[0], p[1]);
            (pl.d, [pl.g[0], pl.g[1], 0.0])
        }
    }
}

/// Signed distance to an ellipsoid centred at the origin (semi-axes `a`), with the outward
/// normal: the nearest point solves a 1D equation in the Lagrange multiplier (Eberly).
fn ellipsoid_distance(a: [f64; 3], p: [f64; 3]) -> Distance {
    let q = [p[0].abs(), p[1].abs(), p[2].abs()];
    let inside = (q[0] / a[0]).powi(2) + (q[1] / a[1]).powi(2) + (q[2] / a[2]).powi(2) < 1.0;
    // Nearest point x_i = a_i² q_i / (a_i² + t), with F(t) = Σ (a_i q_i/(a_i² + t))² − 1 = 0,
    // t ∈ (−min a_i², ∞); F is decreasing there.
    let amin2 = a.iter().fold(f64::INFINITY, |m, v| m.min(v * v));
    let fval = |t: f64| -> f64 {
        (0..3)
            .map(|i| (a[i] * q[i] / (a[i] * a[i] + t)).powi(2))
            .sum::<f64>()
            - 1.0
    };
    let (mut lo, mut hi);
    if inside {
        lo = -amin2;
        hi = 0.0;
    } else {
        lo = 0.0;
        hi = 1.0;
        while fval(hi) > 0.0 {
            hi *= 2.0;
            if hi > 1e30 {
                break;
            }
        }
    }
    // Newton on the decreasing, convex F, kept inside the bracket (bisection otherwise).
    let dfval = |t: f64| -> f64 {
        (0..3)
            .map(|i| -2.0 * (a[i] * q[i]).powi(2) / (a[i] * a[i] + t).powi(3))
            .sum::<f64>()
    };
    let mut t = if inside { 0.5 * (lo + hi) } else { hi };
    for _ in 0..200 {
        let f = fval(t);
        if f > 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        let df = dfval(t);
        let mut next = if df < 0.0 { t - f / df } else { f64::NAN };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - t).abs() <= 1e-15 * (1.0 + t.abs()) || hi - lo <= 1e-15 * (1.0 + hi.abs()) {
            t = next;
            break;
        }
        t = next;
    }

    let x: Vec<f64> = (0..3)
        .map(|i| a[i] * a[i] * q[i] / (a[i] * a[i] + t))
        .collect();
    let diff = [q[0] - x[0], q[1] - x[1], q[2] - x[2]];
    let dist = (diff[0] * diff[0] + diff[1] * diff[1] + diff[2] * diff[2]).sqrt();
    let grad = [
        x[0] / (a[0] * a[0]),
        x[1] / (a[1] * a[1]),
        x[2] / (a[2] * a[2]),
    ];
    let gl = (grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2]).sqrt();
    let n = [
        sign(p[0]) * grad[0] / gl,
        sign(p[1]) * grad[1] / gl,
        sign(p[2]) * grad[2] / gl,
    ];
    Distance {
        d: if inside { -dist } else { dist },
        n,
    }
}
