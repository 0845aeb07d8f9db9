//! The verdict on a design, and the feasibility rule that gives it: the one place that decides
//! whether a drawing is feasible. Everything that shows a verdict (the run summary, the sweep's
//! rows, tables and sheet, the explorer) takes it from here.
//!
//! A design is **feasible** when the drawing reached the full stroke, its result is sound (no
//! deep penetration, no work out of balance), the largest shear stays within the fabric's
//! locking angle and the largest yarn tension within its break tension.

use serde::{Deserialize, Serialize};

/// The verdict on one design. Verdicts order best first (feasible, infeasible, failed,
/// invalid): rankings sort by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum Verdict {
    /// Converged and sound, shear within the locking angle, yarn tension within the break.
    Feasible,
    /// Converged and sound, but over the locking angle or the break tension.
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
    /// Stroke reached and asked for, mm.
    pub stroke_reached_mm: f64,
    pub stroke_mm: f64,
}

impl Facts<'_> {
    pub fn shear_over(&self) -> bool {
        self.max_shear_deg > self.locking_angle_deg
    }

    pub fn tension_over(&self) -> bool {
        self.max_tension_n > self.break_tension_n
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
        } else if f.shear_over() || f.tension_over() {
            Verdict::Infeasible
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
            Verdict::Infeasible => "INFEASIBLE",
            Verdict::Failed => "FAILED",
            Verdict::Invalid => "INVALID",
        }
    }

    /// A one-character mark: ✓ feasible, ✗ infeasible, ! failed, – invalid.
    pub fn mark(self) -> &'static str {
        match self {
            Verdict::Feasible => "✓",
            Verdict::Infeasible => "✗",
            Verdict::Failed => "!",
            Verdict::Invalid => "–",
        }
    }

    /// The verdict of a word written by [`Verdict::word`].
    pub fn parse(word: &str) -> Option<Verdict> {
        Verdict::ALL.into_iter().find(|v| v.word() == word)
    }

    /// Every verdict, best first (the order of rankings).
    pub const ALL: [Verdict; 4] = [
        Verdict::Feasible,
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
    fn words_round_trip() {
        assert!(Verdict::ALL.windows(2).all(|w| w[0] < w[1]), "best first");
        for v in Verdict::ALL {
            assert_eq!(Verdict::parse(v.word()), Some(v));
        }
        assert_eq!(Verdict::parse("maybe"), None);
    }
}
