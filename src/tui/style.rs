//! The explorer's styles (colours, or none on a terminal without them) and the verdict cell
//! that the results table and the detail both show.

use ratatui::style::{Color, Modifier, Style};

use crate::verdict::Verdict;

use super::app::{App, Entry};

pub(super) struct Styles {
    pub(super) colour: bool,
}

impl Styles {
    fn fg(&self, c: Color) -> Style {
        if self.colour {
            Style::default().fg(c)
        } else {
            Style::default()
        }
    }
    pub(super) fn good(&self) -> Style {
        self.fg(Color::Green)
    }
    pub(super) fn bad(&self) -> Style {
        self.fg(Color::Red).add_modifier(Modifier::BOLD)
    }
    pub(super) fn warn(&self) -> Style {
        self.fg(Color::Yellow)
    }
    pub(super) fn dim(&self) -> Style {
        if self.colour {
            Style::default().fg(Color::DarkGray)
        } else {
            Style::default()
        }
    }
    pub(super) fn title(&self) -> Style {
        Style::default().add_modifier(Modifier::BOLD)
    }
    pub(super) fn selected(&self) -> Style {
        if self.colour {
            Style::default().bg(Color::Blue).fg(Color::White)
        } else {
            Style::default().add_modifier(Modifier::REVERSED)
        }
    }
}

/// The verdict in a word, its symbol and its style.
pub(super) fn verdict_cell(entry: &Entry, app: &App, st: &Styles) -> (String, Style) {
    let Some(r) = entry.row.as_ref() else {
        return (if app.running() { "…" } else { "·" }.into(), st.dim());
    };
    let judged = r.judged(entry.limits);
    let style = match judged.verdict {
        Verdict::Feasible => st.good(),
        Verdict::Marginal | Verdict::Failed => st.warn(),
        Verdict::Infeasible => st.bad(),
        Verdict::Invalid => st.dim(),
    };
    (judged.label().into(), style)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::sweep::Row;
    use crate::tui::params::{Parameters, default_source};

    /// The explorer on the default grid with design 0 answered: its max shear
    /// `shear_over_locking` degrees over the locking angle ± 2°, its max tension
    /// `tension_times_break` times the break tension ± 10 %, and the verdict given.
    fn explorer_with(shear_over_locking: f64, tension_times_break: f64, verdict: Verdict) -> App {
        let params = Parameters::new(default_source()).unwrap();
        let mut app = App::new(params, "/session".into(), false);
        let e = &mut app.entries[0];
        let limits = e.limits;
        e.row = Some(Row {
            max_shear_deg: Some(limits.locking_angle_deg + shear_over_locking),
            max_tension_n: Some(limits.break_tension_n * tension_times_break),
            punch_force_n: Some(5000.0),
            max_shear_err_deg: Some(2.0),
            max_tension_err_pct: Some(10.0),
            punch_force_err_pct: Some(5.0),
            converged: true,
            wall_s: Some(3.0),
            ..Row::new(&e.design, e.params.clone(), verdict)
        });
        app
    }

    fn cell(app: &App) -> String {
        verdict_cell(&app.entries[0], app, &Styles { colour: false }).0
    }

    #[test]
    fn an_infeasible_cell_names_the_limit_whose_whole_band_is_over() {
        // The shear 1° over the locking angle, inside its ±2° band; the tension 20 % over the
        // break, its ±10 % band wholly over: infeasible by the tension.
        let by_tension = explorer_with(1.0, 1.2, Verdict::Infeasible);
        assert_eq!(cell(&by_tension), "✗ tension");
        // The converse: the shear's band wholly over, the tension over only inside its band.
        let by_shear = explorer_with(3.0, 1.05, Verdict::Infeasible);
        assert_eq!(cell(&by_shear), "✗ shear");
        // Judged again against the same limits, each keeps its verdict and its reason.
        let mut again = by_tension;
        let limits = again.entries[0].limits;
        again.entries[0].row.as_mut().unwrap().rejudge(limits);
        assert_eq!(cell(&again), "✗ tension");
        assert_eq!(
            cell(&explorer_with(-1.0, 0.5, Verdict::Marginal)),
            "≈ marginal"
        );
    }
}
