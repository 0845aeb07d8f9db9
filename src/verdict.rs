//! The verdict on a design, and the feasibility rule that gives it: the one place that decides
//! whether a drawing is feasible, and which limit decides it. Everything that shows a verdict
//! or its reason (the run summary, the sweep's rows, tables and sheet, the explorer's table,
//! detail and its judging again against edited limits) takes it from here.
//!
//! A design is **feasible** when the drawing reached the full stroke, its result is sound (no
//! deep penetration, no work out of balance), and the largest shear stays within the fabric's
//! locking angle and the largest yarn tension within its break tension by more than their
//! error: the whole error band is on the safe side. It is **infeasible** when a figure is over
//! its limit by more than its error, and **marginal** when a limit lies inside a figure's error
//! band: the answer is too close to call at this accuracy (a finer level may settle it).
//!
//! - [`Limits`]: the fabric's locking angle and break tension.
//! - [`Figures`]: what a run answered (max shear, max tension) with their errors.
//! - [`Judged`]: the rule's answer on trusted figures, a [`Verdict`] and which limit(s)
//!   decide it ([`Over`]), with its label and its sentence.
//! - [`Facts`]: how a run ended, with its figures: the verdict of any run.

use serde::{Deserialize, Serialize};

use crate::scene::Scene;
use crate::show::{Fixed, Num};

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

/// The fabric's limits the figures are judged against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// The shear locking angle, degrees.
    pub locking_angle_deg: f64,
    /// The yarns' break tension, N.
    pub break_tension_n: f64,
    /// The largest wrinkle amplitude allowed, mm (judged only where the model has bending).
    pub wrinkle_limit_mm: f64,
}

impl Limits {
    /// The limits of a scene's fabric.
    pub fn of(scene: &Scene) -> Limits {
        Limits {
            locking_angle_deg: scene.fabric.locking_angle_deg,
            break_tension_n: scene.fabric.break_tension_n,
            wrinkle_limit_mm: scene.fabric.wrinkle_limit_mm,
        }
    }
}

/// The figures a converged, sound run answered, and how far each can be off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Figures {
    pub max_shear_deg: f64,
    pub max_tension_n: f64,
    /// How far the max shear can be off, degrees (0: not known).
    pub max_shear_err_deg: f64,
    /// How far the max tension can be off, % of it (0: not known).
    pub max_tension_err_pct: f64,
    /// The largest wrinkle amplitude, mm, where the model has bending (`None`: the paper's
    /// membrane, which cannot wrinkle: not judged).
    pub max_wrinkle_mm: Option<f64>,
    /// How far the wrinkle amplitude can be off, mm (0: not known).
    pub max_wrinkle_err_mm: f64,
}

/// Where a figure's error band stands against its limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standing {
    /// The whole band is at or under the limit.
    Within,
    /// The limit lies inside the band: too close to call.
    Inside,
    /// The whole band is over the limit.
    Over,
}

impl Standing {
    fn of([lo, hi]: [f64; 2], limit: f64) -> Standing {
        if lo > limit {
            Standing::Over
        } else if lo <= limit && limit < hi {
            Standing::Inside
        } else {
            Standing::Within
        }
    }
}

impl Figures {
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

    /// Where the max shear's, the max tension's and the wrinkle amplitude's bands stand against
    /// their limits (wrinkles: within when the model has no bending).
    pub fn standing(&self, limits: Limits) -> [Standing; 3] {
        let wrinkles = self.max_wrinkle_mm.map_or(Standing::Within, |w| {
            let e = self.max_wrinkle_err_mm.abs();
            Standing::of([w - e, w + e], limits.wrinkle_limit_mm)
        });
        [
            Standing::of(self.shear_band(), limits.locking_angle_deg),
            Standing::of(self.tension_band(), limits.break_tension_n),
            wrinkles,
        ]
    }
}

/// Which limit(s) decide a verdict: for INFEASIBLE the figures whose whole band is over their
/// limit, for MARGINAL those whose band holds their limit, else none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Over {
    pub shear: bool,
    pub tension: bool,
    pub wrinkles: bool,
}

impl Over {
    /// No limit decides.
    pub const NONE: Over = Over {
        shear: false,
        tension: false,
        wrinkles: false,
    };

    fn of([shear, tension, wrinkles]: [bool; 3]) -> Over {
        Over {
            shear,
            tension,
            wrinkles,
        }
    }

    /// The shear decides (alone or with others).
    pub fn shear(self) -> bool {
        self.shear
    }

    /// The tension decides (alone or with others).
    pub fn tension(self) -> bool {
        self.tension
    }

    /// The wrinkles decide (alone or with others).
    pub fn wrinkles(self) -> bool {
        self.wrinkles
    }

    /// No limit decides.
    pub fn is_none(self) -> bool {
        self == Over::NONE
    }
}

/// A verdict and the limit(s) that decide it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Judged {
    pub verdict: Verdict,
    pub over: Over,
}

impl Judged {
    /// The feasibility rule on the figures of a converged, sound run: infeasible when a
    /// figure's whole band is over its limit, marginal when a limit lies inside a band,
    /// feasible otherwise.
    pub fn of(figures: &Figures, limits: Limits) -> Judged {
        let standing = figures.standing(limits);
        let verdict = if standing.contains(&Standing::Over) {
            Verdict::Infeasible
        } else if standing.contains(&Standing::Inside) {
            Verdict::Marginal
        } else {
            Verdict::Feasible
        };
        Judged::explain(verdict, Some(figures), limits)
    }

    /// A verdict given before (a row of `results.csv`, whose figures are rounded), with the
    /// limit(s) that decide it by the error bands of `figures`. A row INFEASIBLE by a hair that
    /// its rounded figures no longer show wholly over is put down to the figures over their
    /// limits by value.
    pub fn explain(verdict: Verdict, figures: Option<&Figures>, limits: Limits) -> Judged {
        let over = match figures {
            Some(f) => {
                let standing = f.standing(limits);
                let by = |s: Standing| Over::of(standing.map(|x| x == s));
                match verdict {
                    Verdict::Infeasible => match by(Standing::Over) {
                        Over::NONE => Over::of([
                            f.max_shear_deg > limits.locking_angle_deg,
                            f.max_tension_n > limits.break_tension_n,
                            f.max_wrinkle_mm
                                .is_some_and(|w| w > limits.wrinkle_limit_mm),
                        ]),
                        over => over,
                    },
                    Verdict::Marginal => by(Standing::Inside),
                    _ => Over::NONE,
                }
            }
            None => Over::NONE,
        };
        Judged { verdict, over }
    }

    /// The judgement of a run with no answer to trust.
    pub fn failed() -> Judged {
        Judged {
            verdict: Verdict::Failed,
            over: Over::NONE,
        }
    }

    /// The verdict in a word and its mark, as the explorer's table shows it: `✓ feasible`,
    /// `≈ marginal`, `✗ shear` or `✗ tension` (the limit that decides it; the shear when both
    /// do), `! failed`, `- invalid`.
    pub fn label(&self) -> &'static str {
        match self.verdict {
            Verdict::Feasible => "✓ feasible",
            Verdict::Marginal => "≈ marginal",
            Verdict::Infeasible if self.over.shear() => "✗ shear",
            Verdict::Infeasible if self.over.tension() => "✗ tension",
            Verdict::Infeasible if self.over.wrinkles() => "✗ wrinkles",
            Verdict::Infeasible => "✗ over",
            Verdict::Failed => "! failed",
            Verdict::Invalid => "- invalid",
        }
    }

    /// The verdict of trusted `figures` in a sentence: `FEASIBLE`, `MARGINAL: the locking
    /// angle … lies within …`, `INFEASIBLE: shear over the locking angle`, ….
    pub fn sentence(&self, figures: &Figures, limits: Limits) -> String {
        match self.verdict {
            Verdict::Marginal => {
                let mut why = Vec::new();
                if self.over.shear() {
                    why.push(format!(
                        "the locking angle {}° lies within the max shear {}° ± {}°",
                        Num(limits.locking_angle_deg),
                        Fixed(figures.max_shear_deg, 1),
                        Fixed(figures.max_shear_err_deg, 1)
                    ));
                }
                if self.over.tension() {
                    why.push(format!(
                        "the break tension {} N lies within the max tension {} N ± {} %",
                        Num(limits.break_tension_n),
                        Fixed(figures.max_tension_n, 0),
                        Fixed(figures.max_tension_err_pct, 0)
                    ));
                }
                if self.over.wrinkles() {
                    why.push(format!(
                        "the wrinkle limit {} mm lies within the wrinkle amplitude {} mm ± {} mm",
                        Num(limits.wrinkle_limit_mm),
                        Fixed(figures.max_wrinkle_mm.unwrap_or(0.0), 2),
                        Fixed(figures.max_wrinkle_err_mm, 2)
                    ));
                }
                format!("MARGINAL: {}", why.join("; "))
            }
            Verdict::Infeasible => {
                let over = if self.over.is_none() {
                    Over::of([true, true, false])
                } else {
                    self.over
                };
                let mut why = Vec::new();
                if over.shear() {
                    why.push("shear over the locking angle");
                }
                if over.tension() {
                    why.push("yarn tension over the break");
                }
                if over.wrinkles() {
                    why.push("wrinkles over the wrinkle limit");
                }
                format!("INFEASIBLE: {}", why.join(", "))
            }
            v => v.word().to_string(),
        }
    }
}

/// What the rule looks at: how the run ended, its figures and the fabric's limits.
#[derive(Clone, Copy, Debug)]
pub struct Facts<'a> {
    pub converged: bool,
    /// The scene has no unique shape (the model has no answer).
    pub no_answer: bool,
    /// Why a converged result cannot be trusted (empty: it can).
    pub unsound: &'a [String],
    pub figures: Figures,
    pub limits: Limits,
    /// Stroke reached and asked for, mm.
    pub stroke_reached_mm: f64,
    pub stroke_mm: f64,
}

impl Facts<'_> {
    /// The run's answer can be used: the full stroke, a sound result.
    pub fn trusted(&self) -> bool {
        self.converged && self.unsound.is_empty()
    }

    /// The verdict of the run: FAILED when its answer cannot be trusted, else the rule's on its
    /// figures ([`Judged::of`]).
    pub fn judge(&self) -> Judged {
        if self.trusted() {
            Judged::of(&self.figures, self.limits)
        } else {
            Judged::failed()
        }
    }

    /// The verdict in a sentence, as the run summary and the maps' titles give it:
    /// `FEASIBLE`, `INFEASIBLE: shear over the locking angle`, `RUN FAILED at stroke …`,
    /// `NOT SOUND: …`, `NO ANSWER: …`.
    pub fn sentence(&self) -> String {
        if self.no_answer {
            return "NO ANSWER: the model has no unique shape for this scene".to_string();
        }
        if !self.converged {
            return format!(
                "RUN FAILED at stroke {:.1} of {:.1} mm",
                self.stroke_reached_mm, self.stroke_mm
            );
        }
        if !self.unsound.is_empty() {
            return format!("NOT SOUND: {}", self.unsound.join("; "));
        }
        self.judge().sentence(&self.figures, self.limits)
    }
}

impl Verdict {
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

    /// The verdict a sentence of [`Facts::sentence`] gives: its first word, or FAILED for a
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
            figures: Figures {
                max_shear_deg: shear,
                max_tension_n: tension,
                max_shear_err_deg: 0.0,
                max_tension_err_pct: 0.0,
                max_wrinkle_mm: None,
                max_wrinkle_err_mm: 0.0,
            },
            limits: Limits {
                locking_angle_deg: 60.0,
                break_tension_n: 1000.0,
                wrinkle_limit_mm: 1.0,
            },
            stroke_reached_mm: 28.0,
            stroke_mm: 28.0,
        }
    }

    fn judge(f: &Facts) -> Verdict {
        f.judge().verdict
    }

    fn sentence(f: &Facts) -> String {
        f.sentence()
    }

    #[test]
    fn the_rule_compares_each_figure_with_its_limit() {
        assert_eq!(judge(&facts(59.9, 999.0)), Verdict::Feasible);
        assert_eq!(judge(&facts(60.0, 1000.0)), Verdict::Feasible);
        assert_eq!(judge(&facts(60.1, 10.0)), Verdict::Infeasible);
        assert_eq!(judge(&facts(10.0, 1000.5)), Verdict::Infeasible);
        let reasons = ["penetration".to_string()];
        let unsound = Facts {
            unsound: &reasons,
            ..facts(10.0, 10.0)
        };
        assert_eq!(judge(&unsound), Verdict::Failed);
        assert!(sentence(&unsound).starts_with("NOT SOUND: penetration"));
        let stopped = Facts {
            converged: false,
            stroke_reached_mm: 12.34,
            ..facts(10.0, 10.0)
        };
        assert_eq!(judge(&stopped), Verdict::Failed);
        assert_eq!(sentence(&stopped), "RUN FAILED at stroke 12.3 of 28.0 mm");
        assert_eq!(
            sentence(&facts(61.0, 1001.0)),
            "INFEASIBLE: shear over the locking angle, yarn tension over the break"
        );
    }

    /// `facts` with the errors ±1° and ±10 %.
    fn banded(shear: f64, tension: f64) -> Facts<'static> {
        let mut f = facts(shear, tension);
        f.figures.max_shear_err_deg = 1.0;
        f.figures.max_tension_err_pct = 10.0;
        f
    }

    #[test]
    fn a_limit_inside_the_error_band_is_marginal() {
        let banded = |shear: f64, tension: f64| banded(shear, tension);
        // 59.03° ± 1°: the band [58.03, 60.03] holds 60°.
        assert_eq!(judge(&banded(59.03, 500.0)), Verdict::Marginal);
        assert_eq!(judge(&banded(60.9, 500.0)), Verdict::Marginal);
        assert_eq!(judge(&banded(58.9, 500.0)), Verdict::Feasible);
        assert_eq!(judge(&banded(61.1, 500.0)), Verdict::Infeasible);
        // 950 N ± 10 %: [855, 1045] holds 1000 N; 1120 N: [1008, 1232] is all over.
        assert_eq!(judge(&banded(30.0, 950.0)), Verdict::Marginal);
        assert_eq!(judge(&banded(30.0, 1120.0)), Verdict::Infeasible);
        assert_eq!(judge(&banded(30.0, 900.0)), Verdict::Feasible);
        // Over one limit by more than its error decides, whatever the other.
        assert_eq!(judge(&banded(61.5, 950.0)), Verdict::Infeasible);
        let s = sentence(&banded(59.03, 500.0));
        assert_eq!(
            s,
            "MARGINAL: the locking angle 60° lies within the max shear 59.0° ± 1.0°"
        );
    }

    #[test]
    fn the_reason_is_the_limit_whose_whole_band_is_over() {
        // Tension 1120 N ± 10 %: [1008, 1232], all over 1000 N; shear 60.5° ± 1°: over 60° by
        // value, but only inside its band. Infeasible by the tension alone.
        let by_tension = banded(60.5, 1120.0);
        let judged = by_tension.judge();
        assert_eq!(judged.verdict, Verdict::Infeasible);
        assert_eq!(
            judged.over,
            Over {
                shear: false,
                tension: true,
                wrinkles: false
            }
        );
        assert_eq!(judged.label(), "✗ tension");
        assert_eq!(
            sentence(&by_tension),
            "INFEASIBLE: yarn tension over the break"
        );
        // The converse: shear 61.5° ± 1° all over 60°; tension 1050 N ± 10 % over 1000 N by
        // value, inside its band.
        let by_shear = banded(61.5, 1050.0);
        let judged = by_shear.judge();
        assert_eq!(
            judged.over,
            Over {
                shear: true,
                tension: false,
                wrinkles: false
            }
        );
        assert_eq!(judged.label(), "✗ shear");
        assert_eq!(
            sentence(&by_shear),
            "INFEASIBLE: shear over the locking angle"
        );
        // Both wholly over.
        let both = banded(61.5, 1120.0).judge();
        assert_eq!(
            (both.over, both.label()),
            (
                Over {
                    shear: true,
                    tension: true,
                    wrinkles: false
                },
                "✗ shear"
            )
        );
        // Marginal: the figures whose band holds the limit; feasible and failed: none.
        let marginal = banded(59.5, 950.0).judge();
        assert_eq!(
            (marginal.verdict, marginal.over),
            (
                Verdict::Marginal,
                Over {
                    shear: true,
                    tension: true,
                    wrinkles: false
                }
            )
        );
        assert_eq!(banded(30.0, 500.0).judge().over, Over::NONE);
        let stopped = Facts {
            converged: false,
            ..banded(61.5, 1120.0)
        };
        assert_eq!(stopped.judge(), Judged::failed());
    }

    #[test]
    fn a_verdict_given_before_is_explained_by_the_bands() {
        let limits = Limits {
            locking_angle_deg: 60.0,
            break_tension_n: 1000.0,
            wrinkle_limit_mm: 1.0,
        };
        let f = banded(60.5, 1120.0).figures;
        let judged = Judged::explain(Verdict::Infeasible, Some(&f), limits);
        assert_eq!(
            (judged.over, judged.label()),
            (
                Over {
                    shear: false,
                    tension: true,
                    wrinkles: false
                },
                "✗ tension"
            )
        );
        // Rounded figures that no longer show a band wholly over: the value over decides.
        let hair = Figures {
            max_tension_n: 1100.0,
            ..f
        };
        let judged = Judged::explain(Verdict::Infeasible, Some(&hair), limits);
        assert_eq!(
            judged.over,
            Over {
                shear: true,
                tension: true,
                wrinkles: false
            }
        );
        assert_eq!(
            Judged::explain(Verdict::Failed, Some(&f), limits).label(),
            "! failed"
        );
        assert_eq!(
            Judged::explain(Verdict::Invalid, None, limits).over,
            Over::NONE
        );
    }

    #[test]
    fn wrinkles_are_judged_where_the_model_has_bending() {
        // No bending: no wrinkle figure, whatever the limit.
        let membrane = facts(30.0, 500.0);
        assert_eq!(judge(&membrane), Verdict::Feasible);
        let with = |mm: f64, err: f64| {
            let mut f = facts(30.0, 500.0);
            f.figures.max_wrinkle_mm = Some(mm);
            f.figures.max_wrinkle_err_mm = err;
            f
        };
        assert_eq!(judge(&with(0.5, 0.05)), Verdict::Feasible);
        // 1.2 ± 0.1 mm against 1 mm: wholly over.
        let over = with(1.2, 0.1);
        assert_eq!(over.judge().label(), "✗ wrinkles");
        assert_eq!(
            sentence(&over),
            "INFEASIBLE: wrinkles over the wrinkle limit"
        );
        // 0.95 ± 0.1 mm: the limit inside the band.
        let close = with(0.95, 0.1);
        assert_eq!(judge(&close), Verdict::Marginal);
        assert!(close.judge().over.wrinkles());
        assert_eq!(
            sentence(&close),
            "MARGINAL: the wrinkle limit 1 mm lies within the wrinkle amplitude 0.95 mm ± 0.10 mm"
        );
        // With the shear over too, both are named; the label gives the shear.
        let mut both = with(1.2, 0.1);
        both.figures.max_shear_deg = 61.0;
        assert_eq!(both.judge().label(), "✗ shear");
        assert_eq!(
            sentence(&both),
            "INFEASIBLE: shear over the locking angle, wrinkles over the wrinkle limit"
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
