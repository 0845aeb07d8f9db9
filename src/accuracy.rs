//! Accuracy levels: how fine the blank is meshed, and the error that buys, measured.
//!
//! A level sets `mesh.element_size`. Its error estimate is the error bound measured on the
//! paper's square box (the open design 10/15/10 and the tight design 5/6/5, linear law, 28 mm
//! stroke) on a mesh ladder (5, 3.54, 2.5, 1.77, 1.25 mm) by `wovenform converge`: each rung's
//! distance to the ladder's reference plus the reference's own uncertainty (see
//! `study::converge`); the larger of the two designs' bounds, rounded up. `wovenform converge
//! presets/paper-box-open.toml --out DIR` (and `…-tight.toml`) reproduces them (README,
//! "Accuracy and speed"). Two designs are not the design space: issue 13 measures the levels
//! across it.

/// How fine a run is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Accuracy {
    Coarse,
    Standard,
    Fine,
}

/// What a level costs and what it is worth on the paper box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorEstimate {
    /// Error of the maximum shear angle, degrees.
    pub max_shear_deg: f64,
    /// Relative error of the punch force, %.
    pub punch_force_pct: f64,
    /// Relative error of the maximum yarn tension, %.
    pub max_tension_pct: f64,
    /// Wall time of the open box on one core, s (what the level costs).
    pub open_box_wall_s: f64,
}

impl Accuracy {
    pub const ALL: [Accuracy; 3] = [Accuracy::Coarse, Accuracy::Standard, Accuracy::Fine];

    pub fn name(self) -> &'static str {
        match self {
            Accuracy::Coarse => "coarse",
            Accuracy::Standard => "standard",
            Accuracy::Fine => "fine",
        }
    }

    /// Reads a level's name; the error lists the names.
    pub fn parse(text: &str) -> Result<Accuracy, String> {
        let t = text.trim();
        Accuracy::ALL
            .into_iter()
            .find(|a| a.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| format!("{t:?}: expected coarse, standard or fine"))
    }

    /// Element size of the blank mesh, mm.
    pub fn element_size_mm(self) -> f64 {
        match self {
            Accuracy::Coarse => 5.0,
            Accuracy::Standard => 2.5,
            Accuracy::Fine => 1.25,
        }
    }

    /// The level whose element size this is, if one is.
    pub fn of_element_size(mm: f64) -> Option<Accuracy> {
        Accuracy::ALL
            .into_iter()
            .find(|a| (a.element_size_mm() - mm).abs() < 1e-9)
    }

    /// The scene overrides that set this level.
    pub fn overrides(self) -> Vec<String> {
        vec![format!("mesh.element_size={:?}", self.element_size_mm())]
    }

    /// The next level up or down (saturating).
    pub fn step(self, up: bool) -> Accuracy {
        let i = Accuracy::ALL.iter().position(|a| *a == self).unwrap_or(1);
        let j = if up {
            (i + 1).min(2)
        } else {
            i.saturating_sub(1)
        };
        Accuracy::ALL[j]
    }

    /// The measured error of this level on the paper box (see the module's comment).
    pub fn error(self) -> ErrorEstimate {
        match self {
            // Bounds: shear open 3.19°, tight 4.32°; force 5.6 %, 6.6 %; tension 28.9 %, 50.0 %.
            Accuracy::Coarse => ErrorEstimate {
                max_shear_deg: 4.5,
                punch_force_pct: 7.0,
                max_tension_pct: 50.0,
                open_box_wall_s: 0.07,
            },
            // Bounds: shear open 1.16°, tight 0.68°; force 2.5 %, 0.7 %; tension 5.2 %, 11.4 %.
            Accuracy::Standard => ErrorEstimate {
                max_shear_deg: 1.2,
                punch_force_pct: 2.5,
                max_tension_pct: 12.0,
                open_box_wall_s: 0.42,
            },
            // Bounds: shear open 0.58°, tight 0.26°; force 0.45 %, 0.54 %; tension 0.9 %, 0.9 %.
            Accuracy::Fine => ErrorEstimate {
                max_shear_deg: 0.6,
                punch_force_pct: 1.0,
                max_tension_pct: 1.0,
                open_box_wall_s: 3.0,
            },
        }
    }
}

impl std::fmt::Display for Accuracy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_errors_shrink_with_the_mesh() {
        for a in Accuracy::ALL {
            assert_eq!(Accuracy::parse(a.name()), Ok(a));
        }
        assert!(
            Accuracy::parse("medium")
                .unwrap_err()
                .contains("coarse, standard or fine")
        );
        let e: Vec<f64> = Accuracy::ALL
            .iter()
            .map(|a| a.error().max_shear_deg)
            .collect();
        assert!(e[0] > e[1] && e[1] > e[2]);
        assert_eq!(Accuracy::Coarse.step(false), Accuracy::Coarse);
        assert_eq!(Accuracy::Standard.step(true), Accuracy::Fine);
        assert_eq!(Accuracy::Standard.overrides(), ["mesh.element_size=2.5"]);
    }
}
