//! Accuracy levels: how fine the blank is meshed, and the error that buys, measured.
//!
//! A level sets `mesh.element_size`. Its error estimate is the error measured on the paper's
//! square box (the open design 10/15/10 and the tight design 5/6/5, linear law, 28 mm stroke)
//! on a mesh ladder (5, 3.54, 2.5, 1.77, 1.25 mm) against its finest rung (the maximum shear
//! does not converge smoothly enough for Richardson) or, for the punch force, its Richardson
//! extrapolation: the larger of the two designs' errors, rounded up. The finest level's error
//! is the change between the two finest rungs. `wovenform converge
//! presets/paper-box-open.toml --out DIR` reproduces the ladder (README, "Accuracy and speed").

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
            // Open 57.00° is 2.61° under the finest rung (force 5.3 % under the Richardson
            // limit), tight 74.40° is 4.27° under it (force 6.4 %).
            Accuracy::Coarse => ErrorEstimate {
                max_shear_deg: 4.5,
                punch_force_pct: 7.0,
                open_box_wall_s: 0.07,
            },
            // Open 59.04° (0.57°, force 2.0 % under the Richardson limit 6,581 N), tight 78.08°
            // (0.59°, force 0.4 %).
            Accuracy::Standard => ErrorEstimate {
                max_shear_deg: 1.0,
                punch_force_pct: 2.5,
                open_box_wall_s: 0.42,
            },
            // The change from the 1.77 mm rung: open 0.35° (force 0.4 %), tight 0.15°
            // (force 1.0 %).
            Accuracy::Fine => ErrorEstimate {
                max_shear_deg: 0.4,
                punch_force_pct: 1.0,
                open_box_wall_s: 3.3,
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
