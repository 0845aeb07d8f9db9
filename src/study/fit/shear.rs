//! The shear law from a bias-extension curve: `k1, k3, k5` of `M(γ) = k1 γ + k3 γ³ + k5 γ⁵`
//! such that the force of the test matches the measured one.
//!
//! The ideal kinematics (`core::specimens::bias`) make the force linear in the coefficients,
//! `F(d) = Σj kj φj(d)` with `φj = γʲ A_c γ' + (γ/2)ʲ A_h γ'/2`, so each pass is a linear
//! least-squares problem on the relative residuals `(F − F_data)/F_data`, solved with
//! `k ≥ 0` (a moment that never softens). The finite-element test departs from the ideal
//! kinematics (the yarns stretch as they decrimp), so the fit can be refined on it: the
//! measured force is divided by the ratio of the finite-element force to the ideal force of
//! the last pass, and fitted again.

use std::path::Path;

use crate::core::fabric::shear::ShearLaw;
use crate::core::specimens::bias::{ideal_force_of, kinematic_limit};

/// One measured point: grip displacement (mm) and force (N).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BiasPoint {
    pub displacement_mm: f64,
    pub force_n: f64,
}

/// Why a bias curve cannot be read or fitted.
#[derive(Debug, thiserror::Error)]
pub enum BiasFitError {
    #[error("{path}: cannot read it: {source}")]
    Unreadable {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}: line {line}: {what}")]
    Bad {
        path: String,
        line: u64,
        what: String,
    },
    #[error(
        "{path}: {count} points with a positive force below {max_shear_deg}° of central shear: expected at least 4"
    )]
    TooFew {
        path: String,
        count: usize,
        max_shear_deg: f64,
    },
}

/// Reads `displacement_mm,force_n` (a UTF-8 BOM allowed; other columns ignored).
pub fn read_bias_curve(path: &Path) -> Result<Vec<BiasPoint>, BiasFitError> {
    let name = path.display().to_string();
    let text = crate::files::read_text(path, crate::files::MAX_TEXT_BYTES).map_err(|source| {
        BiasFitError::Unreadable {
            path: name.clone(),
            source,
        }
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let bad = |line: u64, what: String| BiasFitError::Bad {
        path: name.clone(),
        line,
        what,
    };
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader.headers().map_err(|e| bad(1, e.to_string()))?.clone();
    let column = |c: &str| {
        header.iter().position(|h| h == c).ok_or_else(|| {
            bad(
                1,
                format!(
                    "no column {c} in the header \"{}\": expected displacement_mm,force_n",
                    header.iter().collect::<Vec<_>>().join(",")
                ),
            )
        })
    };
    let (cd, cf) = (column("displacement_mm")?, column("force_n")?);
    let mut points = Vec::new();
    for (i, record) in reader.records().enumerate() {
        let line = i as u64 + 2;
        let record = record.map_err(|e| bad(line, e.to_string()))?;
        let number = |c: usize, name: &str| {
            record
                .get(c)
                .and_then(|v| v.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    bad(
                        line,
                        format!(
                            "{name} = {:?}: expected a number",
                            record.get(c).unwrap_or("")
                        ),
                    )
                })
        };
        points.push(BiasPoint {
            displacement_mm: number(cd, "displacement_mm")?,
            force_n: number(cf, "force_n")?,
        });
    }
    Ok(points)
}

/// The specimen and the range of the fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BiasSpecimen {
    pub length: f64,
    pub width: f64,
    /// Points whose ideal central shear is above this are left out, degrees.
    pub max_shear_deg: f64,
    /// Points below this grip displacement are left out, mm (the initial rise of a measured
    /// curve, a moment at zero shear that no polynomial through 0 follows).
    pub from_mm: f64,
}

/// A fitted shear law and how well it is known.
#[derive(Clone, Debug, PartialEq)]
pub struct ShearFit {
    pub law: ShearLaw,
    /// Points used, and the RMS of the relative and of the absolute residual (N).
    pub points: usize,
    pub rms_rel: f64,
    pub rms_n: f64,
    /// Each coefficient's standard uncertainty relative to its value (∞ when it is 0), and
    /// whether it was held at 0 (freeing it made the moment fall somewhere).
    pub rel_uncertainty: [f64; 3],
    pub at_bound: [bool; 3],
}

impl ShearFit {
    /// Whether coefficient `j` is identified: off its bound and known to within 50 %.
    pub fn identified(&self, j: usize) -> bool {
        !self.at_bound[j] && self.rel_uncertainty[j] <= 0.5
    }
}

/// The ideal-kinematics basis `φj(d)`, N per unit of `kj`.
fn basis(s: &BiasSpecimen, d: f64) -> [f64; 3] {
    [1, 3, 5].map(|j| ideal_force_of(&|g: f64| g.powi(j), s.length, s.width, d))
}

/// The points of the fit: positive force, inside the kinematics and the shear range.
pub fn fit_points(s: &BiasSpecimen, points: &[BiasPoint]) -> Vec<BiasPoint> {
    let limit = kinematic_limit(s.length, s.width);
    points
        .iter()
        .copied()
        .filter(|p| {
            p.force_n > 0.0
                && p.displacement_mm > 0.0
                && p.displacement_mm >= s.from_mm
                && p.displacement_mm < limit
        })
        .filter(|p| {
            crate::core::specimens::bias::ideal_shear(s.length, s.width, p.displacement_mm)
                .to_degrees()
                <= s.max_shear_deg
        })
        .collect()
}

/// Fits `k` to `points` with the measured force divided by `ratio(d)` (1 for the ideal
/// kinematics; the finite-element force over the ideal one when refining): the best law
/// whose moment rises from 0 to 90° (k1 ≥ 0, dM/dγ ≥ 0), over every choice of the
/// coefficients left free (the others at 0).
pub fn fit_shear_law(
    s: &BiasSpecimen,
    points: &[BiasPoint],
    ratio: &dyn Fn(f64) -> f64,
) -> Option<ShearFit> {
    if points.len() < 4 {
        return None;
    }
    // Rows of the relative problem: φj(d)/F_i against 1.
    let rows: Vec<([f64; 3], f64)> = points
        .iter()
        .map(|p| {
            let phi = basis(s, p.displacement_mm).map(|v| v * ratio(p.displacement_mm));
            (phi.map(|v| v / p.force_n), 1.0)
        })
        .collect();
    // Every subset of free coefficients (the rest at 0): the best law that rises.
    let mut best: Option<([f64; 3], f64, [bool; 3])> = None;
    for mask in 1..8u8 {
        let free: Vec<usize> = (0..3).filter(|j| mask & (1 << j) != 0).collect();
        let Some(k_free) = least_squares(&rows, &free) else {
            continue;
        };
        let mut k = [0.0; 3];
        for (i, &j) in free.iter().enumerate() {
            k[j] = k_free[i];
        }
        if !ShearLaw::new(k).rises() {
            continue;
        }
        let sse: f64 = rows
            .iter()
            .map(|(a, b)| (a[0] * k[0] + a[1] * k[1] + a[2] * k[2] - b).powi(2))
            .sum();
        if best.as_ref().is_none_or(|b| sse < b.1 - 1e-15) {
            best = Some((k, sse, [0, 1, 2].map(|j| mask & (1 << j) == 0)));
        }
    }
    let (k, sse, at_bound) = best?;
    let n = rows.len();
    let free: Vec<usize> = (0..3).filter(|&j| !at_bound[j]).collect();
    let dof = (n as f64 - free.len() as f64).max(1.0);
    let sigma2 = sse / dof;
    let mut rel_uncertainty = [f64::INFINITY; 3];
    if let Some(cov) = normal_inverse(&rows, &free) {
        for (i, &j) in free.iter().enumerate() {
            if k[j] != 0.0 {
                rel_uncertainty[j] = (sigma2 * cov[i][i]).sqrt() / k[j].abs();
            }
        }
    }
    let law = ShearLaw::new(k);
    let rms_n = (points
        .iter()
        .map(|p| {
            let f: f64 = basis(s, p.displacement_mm)
                .iter()
                .zip(&k)
                .map(|(a, b)| a * b)
                .sum::<f64>()
                * ratio(p.displacement_mm);
            (f - p.force_n).powi(2)
        })
        .sum::<f64>()
        / n as f64)
        .sqrt();
    Some(ShearFit {
        law,
        points: n,
        rms_rel: (sse / n as f64).sqrt(),
        rms_n,
        rel_uncertainty,
        at_bound,
    })
}

/// The normal matrix `AᵀA` of the columns `free`.
fn normal(rows: &[([f64; 3], f64)], free: &[usize]) -> (Vec<Vec<f64>>, Vec<f64>) {
    let m = free.len();
    let mut ata = vec![vec![0.0; m]; m];
    let mut atb = vec![0.0; m];
    for (a, b) in rows {
        for i in 0..m {
            atb[i] += a[free[i]] * b;
            for j in 0..m {
                ata[i][j] += a[free[i]] * a[free[j]];
            }
        }
    }
    (ata, atb)
}

/// Least squares on the columns `free` (Gauss–Jordan on the normal equations, scaled).
fn least_squares(rows: &[([f64; 3], f64)], free: &[usize]) -> Option<Vec<f64>> {
    let (ata, atb) = normal(rows, free);
    let inv = invert(ata)?;
    Some(
        (0..free.len())
            .map(|i| (0..free.len()).map(|j| inv[i][j] * atb[j]).sum())
            .collect(),
    )
}

fn normal_inverse(rows: &[([f64; 3], f64)], free: &[usize]) -> Option<Vec<Vec<f64>>> {
    invert(normal(rows, free).0)
}

/// The inverse of a small symmetric positive matrix, `None` when it is (nearly) singular
/// (a reciprocal condition below 1e-14 after scaling by the diagonal).
fn invert(a: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let m = a.len();
    let d: Vec<f64> = (0..m).map(|i| a[i][i].sqrt()).collect();
    if d.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return None;
    }
    // Scaled: s = D⁻¹ A D⁻¹, unit diagonal.
    let mut s: Vec<Vec<f64>> = (0..m)
        .map(|i| (0..m).map(|j| a[i][j] / (d[i] * d[j])).collect())
        .collect();
    let mut inv: Vec<Vec<f64>> = (0..m)
        .map(|i| (0..m).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
        .collect();
    for c in 0..m {
        let p = (c..m).max_by(|&x, &y| s[x][c].abs().total_cmp(&s[y][c].abs()))?;
        if s[p][c].abs() < 1e-14 {
            return None;
        }
        s.swap(c, p);
        inv.swap(c, p);
        let pivot = s[c][c];
        for j in 0..m {
            s[c][j] /= pivot;
            inv[c][j] /= pivot;
        }
        for r in 0..m {
            if r != c {
                let f = s[r][c];
                for j in 0..m {
                    s[r][j] -= f * s[c][j];
                    inv[r][j] -= f * inv[c][j];
                }
            }
        }
    }
    Some(
        (0..m)
            .map(|i| (0..m).map(|j| inv[i][j] / (d[i] * d[j])).collect())
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::specimens::bias::ideal_force;

    #[test]
    fn a_curve_made_by_a_law_gives_the_law_back() {
        let s = BiasSpecimen {
            length: 230.0,
            width: 115.0,
            max_shear_deg: 70.0,
            from_mm: 0.0,
        };
        let truth = ShearLaw::new([0.05, 0.02, 0.4]);
        let points: Vec<BiasPoint> = (1..40)
            .map(|i| {
                let d = i as f64;
                BiasPoint {
                    displacement_mm: d,
                    force_n: ideal_force(&truth, 230.0, 115.0, d),
                }
            })
            .collect();
        let fit = fit_shear_law(&s, &fit_points(&s, &points), &|_| 1.0).unwrap();
        for j in 0..3 {
            assert!(
                (fit.law.k[j] - truth.k[j]).abs() < 1e-6 * (1.0 + truth.k[j]),
                "{fit:?}"
            );
        }
        assert!(fit.rms_rel < 1e-9);
    }
}
