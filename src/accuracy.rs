//! Accuracy levels: how fine the blank is meshed, and the error that buys, measured.
//!
//! A level sets `mesh.element_size`. The figures it is judged on are the peaks over one woven
//! cell (`DrawingResult::max_shear`, `max_tension_n`), and its error estimate is measured,
//! then rounded up, on eighteen designs (2026-12-01): the paper's box over its grid (r, rp, rm
//! from 5 to 15 mm, friction 0.1 to 0.3, holder 0.5 to 2 MPa), the hemisphere and the
//! ellipsoid, each solved at 5, 2.5 and 1.25 mm (the fine run of one, 5/6/10, fails). Coarse and standard are compared with the
//! fine answer; the fine level with the 1.77 mm rung and with the exact-disc extrapolation of
//! `guide::findings` ("Accuracy and speed"). The largest distances found:
//!
//! | level | shear | tension | punch force |
//! |---|---|---|---|
//! | coarse (5 mm) | 2.51° | 86 % (box), 154 % (ellipsoid, 140 N against 55 N) | 12.0 % |
//! | standard (2.5 mm) | 0.78° (5/15/10) | 9 % (box), 31.5 % (ellipsoid) | 3.8 % |
//! | fine (1.25 mm) | 0.26° from 1.77 mm | 2.2 % from 1.77 mm | (order ≈ 1.5: about half of standard's) |
//!
//! The fine answer itself carries an error, so each band is wider than the distance to it, and
//! the fine level's band is half the standard's.
//!
//! Re-measured on 2026-12-03 with the solver of that day (the yarn law's toe, steps of at most
//! 1/20 of the stroke): over the 81 designs of `presets/paper-box-sweep.toml` the largest
//! distances to fine were 3.32° (5/6/5, μ 0.15), 119 % and 7.3 % at coarse and 0.73°
//! (5/15/10), 5.6 % and 2.4 % at standard; on 4/8/8, whose 4 mm radius scales the bands by
//! 5/4, coarse lay 4.40° from fine, 3.52° once scaled back to 5 mm, so coarse's shear band
//! went from ±3.5° to ±4°.
//!
//! Those designs' smallest radius is 5 mm or more. Below it the same element size resolves the
//! radius less well: on three boxes with 2 and 3 mm radii (3/3/3, 2/4/2.5, 10/15/2) standard lay
//! 0.85°, 1.27° and 1.25° from fine. So the bands grow as [`MEASURED_RADIUS_MM`] over the
//! smallest radius below it ([`Accuracy::error_for`]).

/// The smallest tool radius the levels' errors were measured down to, mm.
pub const MEASURED_RADIUS_MM: f64 = 5.0;

/// How fine a run is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Accuracy {
    Coarse,
    Standard,
    Fine,
}

/// What a level is worth: how far its figures can be off (what it costs, in run time, is
/// [`crate::study::estimate::run_seconds`] on this machine, or `wovenform bench`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorEstimate {
    /// Error of the maximum shear angle, degrees.
    pub max_shear_deg: f64,
    /// Relative error of the punch force, %.
    pub punch_force_pct: f64,
    /// Relative error of the maximum yarn tension, %.
    pub max_tension_pct: f64,
    /// Error of the wrinkle amplitude (with bending): an absolute part, mm, and a relative
    /// part, % of the amplitude (`guide::bending`, "The bands, measured on drawings that
    /// buckle": a mesh too coarse to follow a wrinkle holds the fabric flat, so a buckling
    /// drawing's figure grows with refinement, and the bands are set from the distances to fine).
    pub max_wrinkle_mm: f64,
    pub max_wrinkle_pct: f64,
}

impl ErrorEstimate {
    /// How far a wrinkle amplitude of `amplitude_mm` can be off, mm.
    pub fn wrinkle_mm(&self, amplitude_mm: f64) -> f64 {
        self.max_wrinkle_mm + amplitude_mm * self.max_wrinkle_pct / 100.0
    }
}

/// A level's name that is none of the levels (as given, trimmed).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{text:?}: expected coarse, standard or fine")]
pub struct UnknownAccuracy {
    pub text: String,
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
    pub fn parse(text: &str) -> Result<Accuracy, UnknownAccuracy> {
        let t = text.trim();
        Accuracy::ALL
            .into_iter()
            .find(|a| a.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| UnknownAccuracy {
                text: t.to_string(),
            })
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

    /// The error of this level on tools whose smallest radius is `smallest_radius_mm`: the
    /// measured one, grown as [`MEASURED_RADIUS_MM`] over the radius below it.
    pub fn error_for(self, smallest_radius_mm: f64) -> ErrorEstimate {
        let e = self.error();
        let k = if smallest_radius_mm > 0.0 {
            (MEASURED_RADIUS_MM / smallest_radius_mm).max(1.0)
        } else {
            1.0
        };
        ErrorEstimate {
            max_shear_deg: k * e.max_shear_deg,
            punch_force_pct: k * e.punch_force_pct,
            max_tension_pct: k * e.max_tension_pct,
            max_wrinkle_mm: e.max_wrinkle_mm,
            max_wrinkle_pct: e.max_wrinkle_pct,
        }
    }

    /// The measured error of this level, for tools whose radii are all 5 mm or more (see the
    /// module's comment).
    pub fn error(self) -> ErrorEstimate {
        match self {
            Accuracy::Coarse => ErrorEstimate {
                max_shear_deg: 4.0,
                punch_force_pct: 15.0,
                max_tension_pct: 160.0,
                max_wrinkle_mm: 0.9,
                max_wrinkle_pct: 300.0,
            },
            Accuracy::Standard => ErrorEstimate {
                max_shear_deg: 1.2,
                punch_force_pct: 5.0,
                max_tension_pct: 35.0,
                max_wrinkle_mm: 0.25,
                max_wrinkle_pct: 100.0,
            },
            Accuracy::Fine => ErrorEstimate {
                max_shear_deg: 0.6,
                punch_force_pct: 2.5,
                max_tension_pct: 15.0,
                max_wrinkle_mm: 0.12,
                max_wrinkle_pct: 100.0,
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
                .to_string()
                .contains("coarse, standard or fine")
        );
        let e: Vec<f64> = Accuracy::ALL
            .iter()
            .map(|a| a.error().max_shear_deg)
            .collect();
        assert!(e[0] > e[1] && e[1] > e[2]);
        // The fine level's error is at most half the standard's, in every figure.
        let (s, f) = (Accuracy::Standard.error(), Accuracy::Fine.error());
        assert!(f.max_shear_deg <= 0.5 * s.max_shear_deg);
        assert!(f.punch_force_pct <= 0.5 * s.punch_force_pct);
        assert!(f.max_tension_pct <= 0.5 * s.max_tension_pct);
        assert_eq!(Accuracy::Coarse.step(false), Accuracy::Coarse);
        assert_eq!(Accuracy::Standard.step(true), Accuracy::Fine);
        assert_eq!(Accuracy::Standard.overrides(), ["mesh.element_size=2.5"]);
        // Radii of 5 mm and more keep the measured band; a 2 mm radius widens it 2.5 times.
        assert_eq!(
            Accuracy::Standard.error_for(10.0),
            Accuracy::Standard.error()
        );
        let small = Accuracy::Standard.error_for(2.0);
        assert!((small.max_shear_deg - 3.0).abs() < 1e-12);
        assert!((small.punch_force_pct - 12.5).abs() < 1e-12);
    }
}
