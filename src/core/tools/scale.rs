//! Whether a mesh tool's size and place can draw the blank at all. STL has no units and
//! wovenform reads mm: a tool written in metres, inches or centimetres is read 1000, 25.4 or
//! 10 times too small, one scaled twice as many times too large, and either may still touch
//! z = 0 and pass every check of its surface. Such a tool is refused before anything is built
//! from it, with its size, what it is compared with, and the unit that would make it fit when
//! one does.
//!
//! What every drawing needs: a punch at least an element across (or the mesh cannot follow
//! it), within the blank (it pushes the blank into an opening the blank covers), at least as
//! tall as the stroke (or the blank's plane passes over its top); a die under the whole blank
//! (its edge rests on the die's face, where the holder presses it).

use std::fmt;

use super::mesh_tool::Role;

/// What a tool is compared with: the blank's sides, the element size and the stroke, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setting {
    pub blank: [f64; 2],
    pub element_mm: f64,
    pub stroke_mm: f64,
}

/// The likely unit mistakes: each unit meant, the factor that reads it as mm (in words) and
/// the tool's plan once scaled. Empty when no usual factor makes the tool fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Hint(Vec<(&'static str, &'static str, [f64; 2])>);

impl Hint {
    /// Whether no usual unit makes the tool fit.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl fmt::Display for Hint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "STL has no units; wovenform reads mm")?;
        if self.0.is_empty() {
            return write!(f, ": is the file in mm?");
        }
        let guesses: Vec<String> = self
            .0
            .iter()
            .map(|(unit, factor, plan)| format!("{unit} ({factor}: {} mm in plan)", pair(*plan)))
            .collect();
        write!(f, ": was it written in {}?", guesses.join(" or "))
    }
}

fn pair(p: [f64; 2]) -> String {
    let show = |v: f64| {
        if v >= 100.0 {
            format!("{v:.0}")
        } else if v >= 1.0 {
            format!("{v:.1}")
        } else {
            format!("{v:.3}")
        }
    };
    format!("{} × {}", show(p[0]), show(p[1]))
}

/// Why a tool cannot draw the blank.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ScaleError {
    #[error(
        "the punch is {} mm in plan, narrower than one element (mesh.element_size = {element_mm} \
         mm): the fabric cannot be drawn over it. {hint}", pair(*plan)
    )]
    PunchTooSmall {
        plan: [f64; 2],
        element_mm: f64,
        hint: Hint,
    },
    #[error(
        "the punch is {} mm in plan, larger than the blank (blank.size = {}): it must fit in \
         the die's opening, which the blank covers. {hint}", pair(*plan), pair(*blank)
    )]
    PunchLargerThanBlank {
        plan: [f64; 2],
        blank: [f64; 2],
        hint: Hint,
    },
    #[error(
        "the punch lies at x {:.1} to {:.1} mm, y {:.1} to {:.1} mm, not within the blank (x and \
         y within ±{:.1} and ±{:.1} mm, centred on x = y = 0): move it over the blank's centre",
        lo[0], hi[0], lo[1], hi[1], 0.5 * blank[0], 0.5 * blank[1]
    )]
    PunchOffBlank {
        lo: [f64; 2],
        hi: [f64; 2],
        blank: [f64; 2],
    },
    #[error(
        "the punch is {height_mm:.3} mm tall, less than the stroke (process.stroke = \
         {stroke_mm} mm): the blank's plane would pass over its top. {hint}"
    )]
    PunchShorterThanStroke {
        height_mm: f64,
        stroke_mm: f64,
        hint: Hint,
    },
    #[error(
        "the die is {} mm in plan, smaller than the blank (blank.size = {}): the blank's edge \
         cannot rest on its face. {hint}", pair(*plan), pair(*blank)
    )]
    DieSmallerThanBlank {
        plan: [f64; 2],
        blank: [f64; 2],
        hint: Hint,
    },
    #[error(
        "the die lies at x {:.1} to {:.1} mm, y {:.1} to {:.1} mm, not under the whole blank (x \
         and y within ±{:.1} and ±{:.1} mm, centred on x = y = 0): move it under the blank's \
         centre", lo[0], hi[0], lo[1], hi[1], 0.5 * blank[0], 0.5 * blank[1]
    )]
    DieOffBlank {
        lo: [f64; 2],
        hi: [f64; 2],
        blank: [f64; 2],
    },
}

/// The usual unit mistakes that leave a tool too small, then too large: the unit meant and
/// the factor that reads it as mm.
type Unit = (&'static str, &'static str, f64);
const TOO_SMALL: [Unit; 3] = [
    ("metres", "×1000", 1000.0),
    ("inches", "×25.4", 25.4),
    ("centimetres", "×10", 10.0),
];
const TOO_LARGE: [Unit; 3] = [
    ("micrometres, or scaled up 1000 times", "÷1000", 0.001),
    ("inches converted to mm twice", "÷25.4", 1.0 / 25.4),
    ("tenths of mm, or scaled up 10 times", "÷10", 0.1),
];

/// How many times the blank a die may be in plan for a unit's guess to be offered (a plate
/// larger still is no die anyone makes for that blank).
const DIE_PLAUSIBLE: f64 = 3.0;

/// The first check of its role that a tool of bounds `(lo, hi)` (mm) fails (with no hint).
fn first_failure(role: Role, (lo, hi): ([f64; 3], [f64; 3]), s: &Setting) -> Option<ScaleError> {
    let plan = [hi[0] - lo[0], hi[1] - lo[1]];
    let (plo, phi) = ([lo[0], lo[1]], [hi[0], hi[1]]);
    let half = s.blank.map(|b| 0.5 * b);
    let hint = Hint(Vec::new());
    match role {
        Role::Punch => {
            if plan[0].min(plan[1]) < s.element_mm {
                let element_mm = s.element_mm;
                return Some(ScaleError::PunchTooSmall {
                    plan,
                    element_mm,
                    hint,
                });
            }
            if plan[0] > s.blank[0] || plan[1] > s.blank[1] {
                let blank = s.blank;
                return Some(ScaleError::PunchLargerThanBlank { plan, blank, hint });
            }
            if (0..2).any(|a| plo[a] < -half[a] || phi[a] > half[a]) {
                let blank = s.blank;
                return Some(ScaleError::PunchOffBlank {
                    lo: plo,
                    hi: phi,
                    blank,
                });
            }
            let height_mm = hi[2] - lo[2];
            (height_mm < s.stroke_mm).then_some(ScaleError::PunchShorterThanStroke {
                height_mm,
                stroke_mm: s.stroke_mm,
                hint,
            })
        }
        Role::Die => {
            if plan[0] < s.blank[0] || plan[1] < s.blank[1] {
                let blank = s.blank;
                return Some(ScaleError::DieSmallerThanBlank { plan, blank, hint });
            }
            (0..2)
                .any(|a| plo[a] > -half[a] || phi[a] < half[a])
                .then_some(ScaleError::DieOffBlank {
                    lo: plo,
                    hi: phi,
                    blank: s.blank,
                })
        }
    }
}

fn scaled((lo, hi): ([f64; 3], [f64; 3]), f: f64) -> ([f64; 3], [f64; 3]) {
    (lo.map(|v| v * f), hi.map(|v| v * f))
}

/// The units that, read as mm, make a tool of bounds `bounds` fit (of the usual mistakes
/// leaving it too small, or too large when `larger`).
pub fn hint(role: Role, bounds: ([f64; 3], [f64; 3]), s: &Setting, larger: bool) -> Hint {
    let candidates = if larger { TOO_LARGE } else { TOO_SMALL };
    Hint(
        candidates
            .iter()
            .filter_map(|&(unit, words, f)| {
                let b = scaled(bounds, f);
                let plan = [b.1[0] - b.0[0], b.1[1] - b.0[1]];
                let plausible =
                    role == Role::Punch || (0..2).all(|a| plan[a] <= DIE_PLAUSIBLE * s.blank[a]);
                (plausible && first_failure(role, b, s).is_none()).then_some((unit, words, plan))
            })
            .collect(),
    )
}

/// Refuses a tool of bounds `bounds` (mm, as placed) that cannot draw the blank of `s`.
pub fn check(role: Role, bounds: ([f64; 3], [f64; 3]), s: &Setting) -> Result<(), ScaleError> {
    let Some(mut e) = first_failure(role, bounds, s) else {
        return Ok(());
    };
    match &mut e {
        ScaleError::PunchTooSmall { hint: h, .. }
        | ScaleError::PunchShorterThanStroke { hint: h, .. }
        | ScaleError::DieSmallerThanBlank { hint: h, .. } => *h = hint(role, bounds, s, false),
        ScaleError::PunchLargerThanBlank { hint: h, .. } => *h = hint(role, bounds, s, true),
        ScaleError::PunchOffBlank { .. } | ScaleError::DieOffBlank { .. } => {}
    }
    Err(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: Setting = Setting {
        blank: [170.0, 170.0],
        element_mm: 5.0,
        stroke_mm: 28.0,
    };
    /// The paper's box tools as `wovenform tools` writes them: a 60 mm punch 38 mm tall, a die
    /// 200 mm square and 38 mm deep.
    const PUNCH: ([f64; 3], [f64; 3]) = ([-30.0, -30.0, 0.0], [30.0, 30.0, 38.0]);
    const DIE: ([f64; 3], [f64; 3]) = ([-100.0, -100.0, -38.0], [100.0, 100.0, 0.0]);

    #[test]
    fn tools_in_mm_pass() {
        assert_eq!(check(Role::Punch, PUNCH, &S), Ok(()));
        assert_eq!(check(Role::Die, DIE, &S), Ok(()));
    }

    #[test]
    fn a_tool_in_other_units_is_named_with_the_unit_that_fits() {
        let says = |role, bounds, factor: f64, words: &[&str]| {
            let e = check(role, scaled(bounds, factor), &S)
                .unwrap_err()
                .to_string();
            for w in words {
                assert!(e.contains(w), "`{w}` not in: {e}");
            }
        };
        says(
            Role::Punch,
            PUNCH,
            0.001,
            &[
                "0.060 × 0.060 mm",
                "narrower than one element",
                "metres",
                "60.0 × 60.0",
            ],
        );
        says(
            Role::Punch,
            PUNCH,
            1.0 / 25.4,
            &["2.4 × 2.4 mm", "inches", "60.0 × 60.0"],
        );
        // A tenth: inches would fit too (a 152 mm punch in a 170 mm blank); both are offered.
        says(
            Role::Punch,
            PUNCH,
            0.1,
            &[
                "3.800 mm tall",
                "less than the stroke",
                "centimetres (×10: 60.0 × 60.0",
                "inches",
            ],
        );
        says(
            Role::Punch,
            PUNCH,
            1000.0,
            &["60000 × 60000 mm", "larger than the blank", "micrometres"],
        );
        says(
            Role::Punch,
            PUNCH,
            25.4,
            &["1524 × 1524", "inches converted to mm twice"],
        );
        says(
            Role::Die,
            DIE,
            0.001,
            &["0.200 × 0.200 mm", "smaller than the blank", "metres"],
        );
        says(
            Role::Die,
            DIE,
            1.0 / 25.4,
            &["7.9 × 7.9 mm", "inches", "200 × 200"],
        );
        // A die far too large still holds the blank in plan: its opening decides (the face
        // raster), and the hint for it is the factor that brings it back.
        assert_eq!(check(Role::Die, scaled(DIE, 1000.0), &S), Ok(()));
        let h = hint(Role::Die, scaled(DIE, 1000.0), &S, true).to_string();
        assert!(h.contains("micrometres") && h.contains("200 × 200"), "{h}");
    }

    #[test]
    fn a_tool_off_the_blank_is_told_to_move() {
        let moved = |(lo, hi): ([f64; 3], [f64; 3]), dx: f64| {
            let mut b = (lo, hi);
            b.0[0] += dx;
            b.1[0] += dx;
            b
        };
        let e = check(Role::Punch, moved(PUNCH, 500.0), &S).unwrap_err();
        assert!(matches!(e, ScaleError::PunchOffBlank { .. }), "{e}");
        let e = check(Role::Die, moved(DIE, 50.0), &S).unwrap_err();
        assert!(matches!(e, ScaleError::DieOffBlank { .. }), "{e}");
    }
}
