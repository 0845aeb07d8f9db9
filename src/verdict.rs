//! The verdict on a design, and the feasibility rule that gives it: the one place that decides
//! whether a drawing is feasible. Everything that shows a verdict (the run summary, the sweep's
//! rows, tables and sheet, the explorer) takes it from here.
//!
//! A design is **feasible** when the drawing reached the full stroke, its result is sound (no
//! deep penetration, no work out of balance), and the largest shear stays within the fabric's
//! locking angle and the largest yarn tension within its break tension by more than their
//! error: the whole error band is on the safe side. It is **infeasible** when a figure is over
//! its limit by more than its error, and **marginal** when a limit lies inside a figure's error
//! band: the answer is too close to call at this accuracy (a finer level may settle it).

use serde::{Deserialize, Serialize};

/// The verdict on one design. Verdicts order best first (feasible, infeasible, failed,
/// invalid): rankings sort by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum Verdict {
    /// Converged and sound, shear within the locking angle, yarn tension within the break,
    /// with their error bands.
    Feasible,
    /// Converged and sound, and a limit lies inside its figure's error band.
    Marginal,
    /// Converged and sound, and over the locking angle or the break tension by more than the
    /// error.
    Infeasible,
    /// No answer to trust: the run stopped short, its result is unsound, the scene has no
    /// unique shape, or the program failed on it.
    Failed,
    /// The design breaks a bound of the scene; it was not run.
    Invalid,
}

/// What the rule looks at: how the run ended, its figures and the fabric's limits.
#[derive(Clone, Copy, Debug)]
pub struct Facts<'a> {
    pub converged: bool,
    /// The scene has no unique shape (the model has no answer).
    pub no_answer: bool,
    /// Why a converged result cannot be trusted (empty: it can).
    pub unsound: &'a [String],
    pub max_shear_deg: f64,
    pub max_tension_n: f64,
    pub locking_angle_deg: f64,
    pub break_tension_n: f64,
    /// How far the max shear can be off, degrees (0: not known).
    pub max_shear_err_deg: f64,
    /// How far the max tension can be off, % of it (0: not known).
    pub max_tension_err_pct: f64,
    /// Stroke reached and asked for, mm.
    pub stroke_reached_mm: f64,
    pub stroke_mm: f64,
}

impl Facts<'_> {
    /// The max shear is over the locking angle (its value, error aside).
    pub fn shear_over(&self) -> bool {
        self.max_shear_deg > self.locking_angle_deg
    }

    /// The max tension is over the break tension (its value, error aside).
    pub fn tension_over(&self) -> bool {
        self.max_tension_n > self.break_tension_n
    }

    /// The band `[low, high]` of the max shear, degrees.
    fn shear_band(&self) -> [f64; 2] {
        let e = self.max_shear_err_deg.abs();
        [self.max_shear_deg - e, self.max_shear_deg + e]
    }

    /// The band `[low, high]` of the max tension, N.
    fn tension_band(&self) -> [f64; 2] {
        let e = self.max_tension_err_pct.abs() / 100.0;
        [
            self.max_tension_n * (1.0 - e),
            self.max_tension_n * (1.0 + e),
        ]
    }

    /// The locking angle lies inside the max shear's band.
    pub fn shear_marginal(&self) -> bool {
        let [lo, hi] = self.shear_band();
        lo <= self.locking_angle_deg && self.locking_angle_deg < hi
    }

    /// The break tension lies inside the max tension's band.
    pub fn tension_marginal(&self) -> bool {
        let [lo, hi] = self.tension_band();
        lo <= self.break_tension_n && self.break_tension_n < hi
    }

    /// The run's answer can be used: the full stroke, a sound result.
    pub fn trusted(&self) -> bool {
        self.converged && self.unsound.is_empty()
    }
}

impl Verdict {
    /// The feasibility rule.
    pub fn judge(f: &Facts) -> Verdict {
        if !f.trusted() {
            Verdict::Failed
        } else if f.shear_band()[0] > f.locking_angle_deg || f.tension_band()[0] > f.break_tension_n
        {
            Verdict::Infeasible
        } else if f.shear_marginal() || f.tension_marginal() {
            Verdict::Marginal
        } else {
            Verdict::Feasible
        }
    }

    /// The verdict in a sentence, as the run summary and the maps' titles give it:
    /// `FEASIBLE`, `INFEASIBLE: shear over the locking angle`, `RUN FAILED at stroke …`,
    /// `NOT SOUND: …`, `NO ANSWER: …`.
    pub fn sentence(f: &Facts) -> String {
        if f.no_answer {
            return "NO ANSWER: the model has no unique shape for this scene".to_string();
        }
        if !f.converged {
            return format!(
                "RUN FAILED at stroke {:.1} of {:.1} mm",
                f.stroke_reached_mm, f.stroke_mm
            );
        }
        if !f.unsound.is_empty() {
            return format!("NOT SOUND: {}", f.unsound.join("; "));
        }
        if Verdict::judge(f) == Verdict::Marginal {
            let mut why = Vec::new();
            if f.shear_marginal() {
                why.push(format!(
                    "the locking angle {}° lies within the max shear {:.1}° ± {:.1}°",
                    f.locking_angle_deg, f.max_shear_deg, f.max_shear_err_deg
                ));
            }
            if f.tension_marginal() {
                why.push(format!(
                    "the break tension {} N lies within the max tension {:.0} N ± {:.0} %",
                    f.break_tension_n, f.max_tension_n, f.max_tension_err_pct
                ));
            }
            return format!("MARGINAL: {}", why.join("; "));
        }
        match (f.shear_over(), f.tension_over()) {
            (false, false) => "FEASIBLE".to_string(),
            (true, false) => "INFEASIBLE: shear over the locking angle".to_string(),
            (false, true) => "INFEASIBLE: yarn tension over the break".to_string(),
            (true, true) => {
                "INFEASIBLE: shear over the locking angle, yarn tension over the break".to_string()
            }
        }
    }

    /// The word written in tables and CSV files.
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Feasible => "FEASIBLE",
            Verdict::Marginal => "MARGINAL",
            Verdict::Infeasible => "INFEASIBLE",
            Verdict::Failed => "FAILED",
            Verdict::Invalid => "INVALID",
        }
    }

    /// A one-character mark: ✓ feasible, ≈ marginal, ✗ infeasible, ! failed, – invalid.
    pub fn mark(self) -> &'static str {
        match self {
            Verdict::Feasible => "✓",
            Verdict::Marginal => "≈",
            Verdict::Infeasible => "✗",
            Verdict::Failed => "!",
            Verdict::Invalid => "–",
        }
    }

    /// The verdict of a word written by [`Verdict::word`].
    pub fn parse(word: &str) -> Option<Verdict> {
        Verdict::ALL.into_iter().find(|v| v.word() == word)
    }

    /// The verdict a sentence of [`Verdict::sentence`] gives: its first word, or FAILED for a
    /// run that cannot be trusted (`RUN FAILED …`, `NOT SOUND: …`, `NO ANSWER: …`).
    pub fn of_sentence(sentence: &str) -> Verdict {
        let word = sentence.split(':').next().unwrap_or("").trim();
        Verdict::parse(word).unwrap_or(Verdict::Failed)
    }

    /// Every verdict, best first (the order of rankings).
    pub const ALL: [Verdict; 5] = [
        Verdict::Feasible,
        Verdict::Marginal,
        Verdict::Infeasible,
        Verdict::Failed,
        Verdict::Invalid,
    ];
}

#[cfg(test)]
mod tests {
    use super::*;

    fn facts(shear: f64, tension: f64) -> Facts<'static> {
        Facts {
            converged: true,
            no_answer: false,
            unsound: &[],
            max_shear_deg: shear,
            max_tension_n: tension,
            locking_angle_deg: 60.0,
            break_tension_n: 1000.0,
            max_shear_err_deg: 0.0,
            max_tension_err_pct: 0.0,
            stroke_reached_mm: 28.0,
            stroke_mm: 28.0,
        }
    }

    #[test]
    fn the_rule_compares_each_figure_with_its_limit() {
        assert_eq!(Verdict::judge(&facts(59.9, 999.0)), Verdict::Feasible);
        assert_eq!(Verdict::judge(&facts(60.0, 1000.0)), Verdict::Feasible);
        assert_eq!(Verdict::judge(&facts(60.1, 10.0)), Verdict::Infeasible);
        assert_eq!(Verdict::judge(&facts(10.0, 1000.5)), Verdict::Infeasible);
        let reasons = ["penetration".to_string()];
        let unsound = Facts {
            unsound: &reasons,
            ..facts(10.0, 10.0)
        };
        assert_eq!(Verdict::judge(&unsound), Verdict::Failed);
        assert!(Verdict::sentence(&unsound).starts_with("NOT SOUND: penetration"));
        let stopped = Facts {
            converged: false,
            stroke_reached_mm: 12.34,
            ..facts(10.0, 10.0)
        };
        assert_eq!(Verdict::judge(&stopped), Verdict::Failed);
        assert_eq!(
            Verdict::sentence(&stopped),
            "RUN FAILED at stroke 12.3 of 28.0 mm"
        );
        assert_eq!(
            Verdict::sentence(&facts(61.0, 1001.0)),
            "INFEASIBLE: shear over the locking angle, yarn tension over the break"
        );
    }

    #[test]
    fn a_limit_inside_the_error_band_is_marginal() {
        let banded = |shear: f64, tension: f64| Facts {
            max_shear_err_deg: 1.0,
            max_tension_err_pct: 10.0,
            ..facts(shear, tension)
        };
        // 59.03° ± 1°: the band [58.03, 60.03] holds 60°.
        assert_eq!(Verdict::judge(&banded(59.03, 500.0)), Verdict::Marginal);
        assert_eq!(Verdict::judge(&banded(60.9, 500.0)), Verdict::Marginal);
        assert_eq!(Verdict::judge(&banded(58.9, 500.0)), Verdict::Feasible);
        assert_eq!(Verdict::judge(&banded(61.1, 500.0)), Verdict::Infeasible);
        // 950 N ± 10 %: [855, 1045] holds 1000 N; 1120 N: [1008, 1232] is all over.
        assert_eq!(Verdict::judge(&banded(30.0, 950.0)), Verdict::Marginal);
        assert_eq!(Verdict::judge(&banded(30.0, 1120.0)), Verdict::Infeasible);
        assert_eq!(Verdict::judge(&banded(30.0, 900.0)), Verdict::Feasible);
        // Over one limit by more than its error decides, whatever the other.
        assert_eq!(Verdict::judge(&banded(61.5, 950.0)), Verdict::Infeasible);
        let s = Verdict::sentence(&banded(59.03, 500.0));
        assert_eq!(
            s,
            "MARGINAL: the locking angle 60° lies within the max shear 59.0° ± 1.0°"
        );
    }

    #[test]
    fn words_round_trip() {
        assert!(Verdict::ALL.windows(2).all(|w| w[0] < w[1]), "best first");
        for v in Verdict::ALL {
            assert_eq!(Verdict::parse(v.word()), Some(v));
        }
        assert_eq!(Verdict::parse("maybe"), None);
        assert_eq!(Verdict::of_sentence("FEASIBLE"), Verdict::Feasible);
        let over = "INFEASIBLE: shear over the locking angle";
        assert_eq!(Verdict::of_sentence(over), Verdict::Infeasible);
        let failed = "RUN FAILED at stroke 3.0 of 4.0 mm";
        assert_eq!(Verdict::of_sentence(failed), Verdict::Failed);
    }
}
