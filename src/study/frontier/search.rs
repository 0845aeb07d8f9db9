//! The search for the boundary along one axis, for one combination of the other axes: plain
//! logic over the runs done so far, which proposes the next runs and, once none is needed,
//! says where the verdict changes.
//!
//! The axis is a lattice of `L` evenly spaced values (index `0..L`); `T` lattice steps make the
//! resolution asked for (one step of the sweep file's grid). Each figure (max shear, max
//! tension, wrinkles) is taken to be monotone along the axis over the range, so the two ends
//! tell which figures cross their limit inside it (a figure over its limit at both ends rules
//! the whole range). Each crossing is then bracketed down to one step: the next run at the
//! root of the linear (or, with a third run, quadratic) model, kept a quarter of the bracket
//! from its ends; half a step past a root that lies within half a step of an end (so that
//! the next bracket is one step wide); the bracket's middle when the same end moved twice
//! running (interpolation creeping along a bent margin); and, once the bracket is two steps
//! or less, the run that leaves one step or less on either side.
//!
//! The MARGINAL zone around a root is read from the runs: the margin taken straight between
//! them, the zone ends where it first stands as far from the limit as the band. A figure that
//! hardly changes near its limit has a wide zone, as it should.

/// The limits a figure is judged against, in the order of the margins.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Governing {
    Shear,
    Tension,
    Wrinkles,
}

impl Governing {
    pub const ALL: [Governing; 3] = [Governing::Shear, Governing::Tension, Governing::Wrinkles];

    /// The name in tables: `shear`, `tension`, `wrinkles`.
    pub fn name(self) -> &'static str {
        match self {
            Governing::Shear => "shear",
            Governing::Tension => "tension",
            Governing::Wrinkles => "wrinkles",
        }
    }
}

/// What one run answered, as the search sees it: for each figure its margin (figure − limit,
/// in the figure's unit; `None`: not judged) and its error band (half width, same unit); or
/// why there is no answer.
#[derive(Clone, Debug, PartialEq)]
pub enum Answer {
    Margins {
        margin: [Option<f64>; 3],
        band: [f64; 3],
    },
    None(String),
}

impl Answer {
    fn margin(&self, k: usize) -> Option<f64> {
        match self {
            Answer::Margins { margin, .. } => margin[k],
            Answer::None(_) => None,
        }
    }

    fn band(&self, k: usize) -> f64 {
        match self {
            Answer::Margins { band, .. } => band[k],
            Answer::None(_) => 0.0,
        }
    }

    /// Over some limit (central figures).
    pub fn over(&self) -> Option<bool> {
        match self {
            Answer::Margins { margin, .. } => Some(margin.iter().flatten().any(|m| *m > 0.0)),
            Answer::None(_) => None,
        }
    }
}

/// A root of one figure's margin: where the verdict may change.
#[derive(Clone, Debug, PartialEq)]
pub struct Root {
    pub governing: Governing,
    /// The estimate and the search's interval, lattice units (fractional).
    pub at: f64,
    pub search: [f64; 2],
    /// The MARGINAL zone around it (where the figure lies within its band of the limit, the
    /// margin taken straight between runs), lattice units.
    pub zone: [f64; 2],
    /// The side where this figure is under its limit: above the root (`true`) or below.
    pub under_above: bool,
}

/// What the search came to.
#[derive(Clone, Debug, PartialEq)]
pub enum Found {
    /// The verdict changes at these roots (sorted along the axis).
    Boundaries(Vec<Root>),
    /// The verdict does not change over the range searched (`[lo, hi]`, lattice indices):
    /// over some limit everywhere (the figures over at some run), or under them all.
    Whole {
        over: Vec<Governing>,
        range: [usize; 2],
    },
    /// No run answered at either end (every try failed): why.
    NoAnswer(String),
}

/// The search along one combination's axis.
#[derive(Clone, Debug)]
pub struct Search {
    lattice: usize,
    step: usize,
    /// Runs at most (then the brackets are what they are).
    budget: usize,
    /// The runs so far, sorted by lattice index.
    points: Vec<(usize, Answer)>,
    /// Their lattice indices in the order they were added.
    order: Vec<usize>,
}

impl Search {
    /// A search over `lattice` values where `step` of them make the resolution, with at most
    /// `budget` runs.
    pub fn new(lattice: usize, step: usize, budget: usize) -> Search {
        Search {
            lattice: lattice.max(2),
            step: step.clamp(1, lattice.max(2) - 1),
            budget: budget.max(2),
            points: Vec::new(),
            order: Vec::new(),
        }
    }

    /// The runs so far.
    pub fn runs(&self) -> usize {
        self.points.len()
    }

    /// The runs that did not answer (failed or invalid): where and why.
    pub fn failures(&self) -> Vec<(usize, String)> {
        (self.points.iter())
            .filter_map(|(i, a)| match a {
                Answer::None(why) => Some((*i, why.clone())),
                Answer::Margins { .. } => None,
            })
            .collect()
    }

    /// A run at lattice index `i` is among them.
    pub fn has(&self, i: usize) -> bool {
        self.points.iter().any(|(j, _)| *j == i)
    }

    /// Adds a run's answer (a run already there is replaced).
    pub fn add(&mut self, index: usize, answer: Answer) {
        self.points.retain(|(j, _)| *j != index);
        self.points.push((index, answer));
        self.points.sort_by_key(|(j, _)| *j);
        self.order.retain(|j| *j != index);
        self.order.push(index);
    }

    fn good(&self) -> Vec<(usize, &Answer)> {
        let good = self.points.iter().filter(|(_, a)| a.over().is_some());
        good.map(|(i, a)| (*i, a)).collect()
    }

    /// The runs to do next (none: the search is over).
    pub fn next(&self) -> Vec<usize> {
        let ends = self.ends_to_try();
        if !ends.is_empty() || self.ends().is_none() {
            return ends;
        }
        if self.runs() >= self.budget {
            return Vec::new();
        }
        let mut wanted: Vec<usize> = (self.open_brackets().iter())
            .filter_map(|b| self.proposal(b))
            .collect();
        wanted.sort_unstable();
        wanted.dedup();
        wanted.truncate(self.budget - self.runs());
        wanted
    }

    /// The ends of the range that answered: the outermost runs with figures.
    fn ends(&self) -> Option<[usize; 2]> {
        let good = self.good();
        Some([good.first()?.0, good.last()?.0])
    }

    /// The ends still to try: the range's ends, and where a run there failed, one
    /// resolution step further in (until the two ends meet).
    fn ends_to_try(&self) -> Vec<usize> {
        let last = self.lattice - 1;
        let mut out = Vec::new();
        let (mut lo, mut hi) = (0usize, last);
        let low_done = loop {
            if lo > hi {
                break true;
            }
            match self.points.iter().find(|(j, _)| *j == lo) {
                None => break false,
                Some((_, a)) if a.over().is_some() => break true,
                Some(_) => lo += self.step,
            }
        };
        if !low_done {
            out.push(lo);
        }
        let high_done = loop {
            if hi < lo || (low_done && self.ends().is_some_and(|[l, _]| hi <= l)) {
                break true;
            }
            match self.points.iter().find(|(j, _)| *j == hi) {
                None => break false,
                Some((_, a)) if a.over().is_some() => break true,
                Some(_) => match hi.checked_sub(self.step) {
                    Some(h) => hi = h,
                    None => break true,
                },
            }
        };
        if !high_done && !out.contains(&hi) {
            out.push(hi);
        }
        out
    }

    /// Brackets of a figure's sign change between neighbouring runs that answered, which
    /// matter (no other figure is over at both of its ends) and are not yet resolved.
    fn open_brackets(&self) -> Vec<Bracket> {
        self.brackets()
            .into_iter()
            .filter(|b| b.matters && !self.closed(b))
            .collect()
    }

    /// Every sign change of a figure's margin between neighbouring runs that answered.
    fn brackets(&self) -> Vec<Bracket> {
        let good = self.good();
        let mut out = Vec::new();
        for (k, _) in Governing::ALL.iter().enumerate() {
            for pair in good.windows(2) {
                let [(a, pa), (b, pb)] = [pair[0], pair[1]];
                let (Some(ma), Some(mb)) = (pa.margin(k), pb.margin(k)) else {
                    continue;
                };
                if (ma > 0.0) == (mb > 0.0) {
                    continue;
                }
                let others_over = (0..3).filter(|&j| j != k).any(|j| {
                    pa.margin(j).is_some_and(|m| m > 0.0) && pb.margin(j).is_some_and(|m| m > 0.0)
                });
                out.push(Bracket {
                    k,
                    a,
                    b,
                    ma,
                    mb,
                    matters: !others_over,
                });
            }
        }
        out
    }

    /// A third run beside the bracket (the nearer neighbour outside it) for the quadratic.
    fn third(&self, br: &Bracket) -> Option<(f64, f64)> {
        let good = self.good();
        let below = good.iter().rev().find(|(i, _)| *i < br.a);
        let above = good.iter().find(|(i, _)| *i > br.b);
        let pick = match (below, above) {
            (Some(l), Some(h)) if br.a - l.0 <= h.0 - br.b => l,
            (Some(l), None) => l,
            (_, Some(h)) => h,
            (None, None) => return None,
        };
        Some((pick.0 as f64, pick.1.margin(br.k)?))
    }

    /// The roots the linear and (with a third run) the quadratic model put in the bracket.
    fn models(&self, br: &Bracket) -> (f64, Option<f64>) {
        let (a, b) = (br.a as f64, br.b as f64);
        let linear = a + (b - a) * br.ma / (br.ma - br.mb);
        let quadratic = self
            .third(br)
            .and_then(|(c, mc)| quadratic_root([(a, br.ma), (b, br.mb), (c, mc)], a, b));
        (linear, quadratic)
    }

    /// The bracket is closed: one step wide or less.
    fn closed(&self, br: &Bracket) -> bool {
        br.b - br.a <= self.step
    }

    /// When in the run order lattice index `i` was added.
    fn when(&self, i: usize) -> usize {
        self.order.iter().position(|j| *j == i).unwrap_or(0)
    }

    /// The same end of the bracket moved twice running (its latest end and the run beyond it
    /// both came from the search, after the other end): interpolation is creeping along a
    /// bent margin, so the next run halves the bracket instead.
    fn creeping(&self, br: &Bracket) -> bool {
        let Some([lo, hi]) = self.ends() else {
            return false;
        };
        let interior = |i: usize| i > lo && i < hi;
        let (recent, other) = if self.when(br.b) > self.when(br.a) {
            (br.b, br.a)
        } else {
            (br.a, br.b)
        };
        let good = self.good();
        let beyond = if recent == br.b {
            good.iter().find(|(i, _)| *i > br.b)
        } else {
            good.iter().rev().find(|(i, _)| *i < br.a)
        };
        interior(recent)
            && beyond.is_some_and(|(p, _)| interior(*p) && self.when(*p) > self.when(other))
    }

    /// The next run for an open bracket. Wider than two steps: the models' root (or the
    /// middle, when interpolation creeps), kept a quarter of the bracket from its ends, or
    /// half a step past a root within half a step of an end. Two steps or less: the run
    /// nearest the models' root that leaves one step or less on either side.
    fn proposal(&self, br: &Bracket) -> Option<usize> {
        let (linear, quadratic) = self.models(br);
        let guess = quadratic.unwrap_or(linear);
        let t = self.step as f64;
        let (a, b) = (br.a as f64, br.b as f64);
        let target = if b - a <= 2.0 * t {
            guess.clamp(b - t, a + t)
        } else if self.creeping(br) {
            (a + b) / 2.0
        } else if guess - a < t / 2.0 {
            guess + t / 2.0
        } else if b - guess < t / 2.0 {
            guess - t / 2.0
        } else {
            let quarter = (b - a) / 4.0;
            guess.clamp(a + quarter, b - quarter)
        };
        let i = (target.round() as usize).clamp(br.a + 1, br.b - 1);
        if !self.has(i) {
            return Some(i);
        }
        // Taken (a run there failed): the nearest untried index inside the bracket.
        (1..br.b - br.a)
            .flat_map(|d| [i.checked_sub(d), Some(i + d)])
            .flatten()
            .find(|&j| j > br.a && j < br.b && !self.has(j))
    }

    /// What the search came to (with the runs so far).
    pub fn found(&self) -> Found {
        let Some([lo, hi]) = self.ends() else {
            let why = self.points.iter().find_map(|(_, a)| match a {
                Answer::None(w) => Some(w.clone()),
                Answer::Margins { .. } => None,
            });
            return Found::NoAnswer(why.unwrap_or_else(|| "no run yet".into()));
        };
        let mut roots: Vec<Root> = (self.brackets().iter())
            .filter(|b| b.matters)
            .map(|b| self.root(b))
            .collect();
        roots.sort_by(|x, y| x.at.total_cmp(&y.at));
        if !roots.is_empty() {
            return Found::Boundaries(roots);
        }
        let good = self.good();
        let over = Governing::ALL
            .iter()
            .enumerate()
            .filter(|(k, _)| {
                good.iter()
                    .any(|(_, a)| a.margin(*k).is_some_and(|m| m > 0.0))
            })
            .map(|(_, g)| *g)
            .collect();
        Found::Whole {
            over,
            range: [lo, hi],
        }
    }

    /// A bracket's root: the estimate, the search's interval and the MARGINAL zone.
    fn root(&self, br: &Bracket) -> Root {
        let (a, b) = (br.a as f64, br.b as f64);
        let (linear, quadratic) = self.models(br);
        // In a closed bracket the straight line between its runs is the estimate.
        let at = if self.closed(br) {
            linear
        } else {
            quadratic.unwrap_or(linear)
        }
        .clamp(a, b);
        Root {
            governing: Governing::ALL[br.k],
            at,
            search: [a, b],
            zone: [self.zone_edge(br, at, false), self.zone_edge(br, at, true)],
            under_above: br.mb <= 0.0,
        }
    }

    /// The MARGINAL zone's edge below (or `above`) a root at `at`: where the margin, straight
    /// between the runs, first stands as far from the limit as the band; the outermost run
    /// when every run that way is inside its band.
    fn zone_edge(&self, br: &Bracket, at: f64, above: bool) -> f64 {
        let mut runs: Vec<(f64, f64)> = (self.good().iter())
            .filter_map(|(i, p)| Some((*i as f64, p.margin(br.k)?.abs() - p.band(br.k))))
            .filter(|(x, _)| {
                if above {
                    *x >= br.b as f64
                } else {
                    *x <= br.a as f64
                }
            })
            .collect();
        if !above {
            runs.reverse();
        }
        // From the root (where the margin is 0, inside any band) outward.
        let (mut x0, mut h0) = (at, -f64::MIN_POSITIVE);
        for (x, h) in runs {
            if h > 0.0 {
                if x0 == at {
                    // Inside the bracket the margin is straight from 0 at the root: the edge
                    // is where it reaches the band.
                    let (m, band) = self.margin_and_band(br, x as usize);
                    return at + (x - at) * band / m.abs().max(band);
                }
                return x0 + (x - x0) * (-h0) / (h - h0);
            }
            (x0, h0) = (x, h);
        }
        x0
    }

    /// A run's margin and band for the bracket's figure.
    fn margin_and_band(&self, br: &Bracket, i: usize) -> (f64, f64) {
        let p = &self.points.iter().find(|(j, _)| *j == i).expect("a run").1;
        (p.margin(br.k).unwrap_or(0.0), p.band(br.k))
    }
}

/// A sign change of figure `k`'s margin between neighbouring runs `a < b`.
#[derive(Clone, Copy, Debug)]
struct Bracket {
    k: usize,
    a: usize,
    b: usize,
    ma: f64,
    mb: f64,
    /// No other figure is over at both ends (else the verdict does not change here).
    matters: bool,
}

/// The root in `[lo, hi]` of the parabola through three points, if it has one there.
fn quadratic_root(p: [(f64, f64); 3], lo: f64, hi: f64) -> Option<f64> {
    let [(x0, y0), (x1, y1), (x2, y2)] = p;
    // Newton's divided differences: y = y0 + d1 (x − x0) + d2 (x − x0)(x − x1).
    let d01 = (y1 - y0) / (x1 - x0);
    let d12 = (y2 - y1) / (x2 - x1);
    let d2 = (d12 - d01) / (x2 - x0);
    // In powers of (x − x0): y0 + (d01 − d2 (x1 − x0)) u + d2 u².
    let (a, b, c) = (d2, d01 - d2 * (x1 - x0), y0);
    let roots: Vec<f64> = if a.abs() < 1e-12 * (b.abs() + 1e-300) {
        if b == 0.0 { vec![] } else { vec![-c / b] }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        // The stable pair of roots.
        let q = -0.5 * (b + b.signum() * s);
        let mut r = vec![q / a];
        if q != 0.0 {
            r.push(c / q);
        }
        r
    };
    roots
        .into_iter()
        .map(|u| x0 + u)
        .filter(|x| x.is_finite() && *x >= lo && *x <= hi)
        .min_by(|p, q| {
            (p - (lo + hi) / 2.0)
                .abs()
                .total_cmp(&(q - (lo + hi) / 2.0).abs())
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs a search on margins given by `f` (per figure, of the lattice index), with bands
    /// `band`; returns what it found and the runs it took.
    fn drive(
        lattice: usize,
        step: usize,
        f: impl Fn(f64) -> [Option<f64>; 3],
        band: [f64; 3],
    ) -> (Found, usize) {
        let mut s = Search::new(lattice, step, 9);
        for _ in 0..40 {
            let next = s.next();
            if next.is_empty() {
                break;
            }
            for i in next {
                s.add(
                    i,
                    Answer::Margins {
                        margin: f(i as f64),
                        band,
                    },
                );
            }
        }
        (s.found(), s.runs())
    }

    #[test]
    fn a_straight_margin_is_found_in_three_or_four_runs_within_half_a_step() {
        // Shear falls 1.3° a lattice unit and crosses its limit at 23.4 of 64.
        let (found, runs) = drive(
            65,
            8,
            |x| [Some(1.3 * (23.4 - x)), Some(-100.0), None],
            [2.6, 10.0, 0.0],
        );
        let Found::Boundaries(roots) = found else {
            panic!("{found:?}")
        };
        assert_eq!(roots.len(), 1);
        let r = &roots[0];
        assert_eq!(r.governing, Governing::Shear);
        assert!(r.under_above);
        assert!((r.at - 23.4).abs() < 0.5, "{r:?}");
        assert!(r.search[0] <= 23.4 && 23.4 <= r.search[1], "{r:?}");
        assert!(r.search[1] - r.search[0] <= 8.0, "{r:?}");
        // Band 2.6° over a slope of 1.3° per unit: two units either side.
        assert!(
            (r.zone[0] - 21.4).abs() < 1e-9 && (r.zone[1] - 25.4).abs() < 1e-9,
            "{r:?}"
        );
        assert!(runs <= 4, "{runs} runs");
    }

    #[test]
    fn a_curved_margin_is_bracketed_to_one_step() {
        // A root at 41.7 of a margin that bends strongly (exponential).
        let g = |x: f64| (0.08 * (x - 41.7)).exp() - 1.0;
        let (found, runs) = drive(65, 8, |x| [None, Some(g(x)), None], [0.0; 3]);
        let Found::Boundaries(roots) = found else {
            panic!("{found:?}")
        };
        let r = &roots[0];
        assert_eq!(r.governing, Governing::Tension);
        assert!(!r.under_above);
        assert!(r.search[0] <= 41.7 && 41.7 <= r.search[1], "{r:?}");
        assert!(r.search[1] - r.search[0] <= 8.0, "{r:?}");
        assert!(runs <= 6, "{runs} runs");
    }

    #[test]
    fn a_margin_that_falls_fast_then_lies_flat_is_still_bracketed() {
        // Shear 6.6° over at 0, falling steeply to the limit at 21.2 of 64, then within 1.5°
        // of it (the paper's box with rp 15, rm 7.5 mm at standard): interpolation alone
        // creeps along the flat part; the bracket must still close on the root.
        let g = |x: f64| {
            if x < 24.0 {
                6.6 - 6.6 * (x / 21.2).powf(0.8)
            } else {
                let at24 = 6.6 - 6.6 * (24.0f64 / 21.2).powf(0.8);
                at24 - 1.0 * (x - 24.0) / 40.0
            }
        };
        let (found, runs) = drive(
            65,
            8,
            |x| [Some(g(x)), Some(-500.0), None],
            [1.2, 100.0, 0.0],
        );
        let Found::Boundaries(roots) = found else {
            panic!("{found:?}")
        };
        let r = &roots[0];
        assert!(
            r.search[0] <= 21.2 && 21.2 <= r.search[1],
            "{r:?} in {runs} runs"
        );
        assert!(r.search[1] - r.search[0] <= 8.0, "{r:?}");
        // Within the band (1.2°) from about 17 up to 44.4, where the flat part has fallen
        // 1.2° under the limit: the zone says so.
        assert!((r.zone[1] - 44.4).abs() < 0.5, "{r:?}");
        assert!(r.zone[0] > 14.0 && r.zone[0] < 19.0, "{r:?}");
        assert!(runs <= 8, "{runs} runs");
    }

    #[test]
    fn a_window_is_two_boundaries() {
        // Shear over below 12.2, tension over above 50.5: feasible between.
        let (found, runs) = drive(
            65,
            8,
            |x| [Some(0.9 * (12.2 - x)), Some(20.0 * (x - 50.5)), None],
            [1.0, 30.0, 0.0],
        );
        let Found::Boundaries(roots) = found else {
            panic!("{found:?}")
        };
        assert_eq!(roots.len(), 2, "{roots:?}");
        assert_eq!(roots[0].governing, Governing::Shear);
        assert_eq!(roots[1].governing, Governing::Tension);
        assert!(roots[0].under_above && !roots[1].under_above);
        for (r, x) in roots.iter().zip([12.2, 50.5]) {
            assert!(r.search[0] <= x && x <= r.search[1], "{r:?}");
        }
        assert!(runs <= 9, "{runs} runs");
    }

    #[test]
    fn no_change_says_which_side_in_two_runs() {
        let (found, runs) = drive(65, 8, |x| [Some(5.0 + x), Some(-1.0), None], [1.0; 3]);
        assert_eq!(
            found,
            Found::Whole {
                over: vec![Governing::Shear],
                range: [0, 64]
            }
        );
        assert_eq!(runs, 2);
        // A root of tension where shear is over at both ends does not change the verdict.
        let (found, _) = drive(65, 8, |x| [Some(5.0 + x), Some(x - 30.0), None], [1.0; 3]);
        assert!(matches!(found, Found::Whole { .. }), "{found:?}");
    }

    #[test]
    fn a_failed_end_moves_the_end_in_by_a_step() {
        let mut s = Search::new(65, 8, 9);
        assert_eq!(s.next(), [0, 64]);
        s.add(0, Answer::None("stopped at 20 of 28 mm".into()));
        s.add(
            64,
            Answer::Margins {
                margin: [Some(-1.0), None, None],
                band: [0.5; 3],
            },
        );
        assert_eq!(s.next(), [8]);
        let mut all_failed = Search::new(17, 8, 9);
        for i in [0, 16, 8] {
            all_failed.add(i, Answer::None("no".into()));
        }
        assert!(all_failed.next().is_empty());
        assert!(matches!(all_failed.found(), Found::NoAnswer(_)));
    }

    #[test]
    fn the_parabola_root_is_the_one_inside() {
        // y = (x − 2)(x − 7): roots 2 and 7.
        let y = |x: f64| (x - 2.0) * (x - 7.0);
        let p = [(0.0, y(0.0)), (5.0, y(5.0)), (9.0, y(9.0))];
        let r = quadratic_root(p, 5.0, 9.0).unwrap();
        assert!((r - 7.0).abs() < 1e-12, "{r}");
        let r = quadratic_root(p, 0.0, 5.0).unwrap();
        assert!((r - 2.0).abs() < 1e-12, "{r}");
    }
}
