//! The frontier's grid: the sweep file's axis along which the boundary is searched, made a
//! fine lattice over the same range (a sweep plan like any other, so that each run is a
//! design of it, a row of `results.csv`), and the combinations of the other axes.

use super::super::sweep::{Axis, Design, Plan, SweepError, as_number, fnv_hex, show_value};

/// Lattice values per step of the sweep file's axis: a run's value is rounded to an eighth of
/// the resolution asked for.
pub const PER_STEP: usize = 8;

/// Positive values spanning this factor or more make a lattice even in the logarithm (a
/// holder pressure from 0.01 to 10 MPa), as the charts draw them.
pub const LOG_SPAN: f64 = 30.0;

/// The lattice plan and where each combination's runs sit in it.
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    /// The sweep plan with the axis replaced by the lattice.
    pub plan: Plan,
    /// The axis's place among the plan's axes.
    pub axis: usize,
    /// The range searched and the sweep file's number of values on it.
    pub lo: f64,
    pub hi: f64,
    pub grid_values: usize,
    /// Evenly spaced in the logarithm (positive values spanning [`LOG_SPAN`] or more), else
    /// evenly spaced.
    pub log: bool,
    /// The lattice's designs, in grid order.
    pub designs: Vec<Design>,
    /// Each combination of the other axes: one value index per axis (the searched one 0).
    pub combos: Vec<Vec<usize>>,
}

impl Lattice {
    /// The lattice along `key` (a scene key or a short name swept in the file with two or more
    /// numbers) of `plan`, asked for with `--along KEY`.
    pub fn new(plan: &Plan, key: &str) -> Result<Lattice, SweepError> {
        Lattice::asked_with(plan, key, "--along")
    }

    /// [`Lattice::new`], the axis named by the option `flag` (`--along`, `slurm --frontier`)
    /// in errors.
    pub fn asked_with(plan: &Plan, key: &str, flag: &str) -> Result<Lattice, SweepError> {
        let bad = |detail: String| {
            SweepError::BadInput(format!("{}: {flag} {key}: {detail}", plan.sweep_file))
        };
        let swept: Vec<&str> = plan.axes.iter().map(|a| a.column.as_str()).collect();
        let Some(axis) = plan
            .axes
            .iter()
            .position(|a| a.key == key || a.column == key)
        else {
            return Err(bad(format!(
                "not a swept key; expected one of the [sweep] table's: {}",
                swept.join(", ")
            )));
        };
        let a = &plan.axes[axis];
        let numbers: Option<Vec<f64>> = a.values.iter().map(as_number).collect();
        let Some(numbers) = numbers.filter(|n| n.len() >= 2) else {
            let given: Vec<String> = a.values.iter().map(show_value).collect();
            return Err(bad(format!(
                "sweep.{} = [{}]; expected two or more numbers (the range to search, and by \
                 their count the resolution)",
                a.column,
                given.join(", ")
            )));
        };
        // A whole-number key (a seed, a count) has no value between two of its values.
        if a.values
            .iter()
            .all(|v| matches!(v, toml::Value::Integer(_)))
            && integer_key(plan, &a.key)
        {
            return Err(bad(format!(
                "{} takes whole numbers (a seed or a count), which have no boundary between \
                 them; expected a key that takes any number (a radius, a pressure, a \
                 coefficient): sweep it with `wovenform sweep` instead",
                a.key
            )));
        }
        let lo = numbers.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = numbers.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let count = (numbers.len() - 1) * PER_STEP + 1;
        let log = lo > 0.0 && hi >= LOG_SPAN * lo;
        let values = (0..count)
            .map(|j| toml::Value::Float(tidy(at(lo, hi, log, j as f64 / (count - 1) as f64))))
            .collect();
        let mut lattice = plan.clone();
        lattice.axes[axis] = Axis {
            values,
            ..a.clone()
        };
        let sweep_json = serde_json::to_string(&lattice.axes).expect("the axes are plain data");
        lattice.sweep_hash = fnv_hex(&format!("{}\n{sweep_json}", lattice.base_hash));
        let size = (lattice.axes.iter()).try_fold(1usize, |n, a| n.checked_mul(a.values.len()));
        if size.is_none_or(|n| n > MAX_DESIGNS) {
            return Err(bad(format!(
                "the lattice would hold {} designs ({PER_STEP} per step of the sweep file's \
                 {} values, times the other axes' combinations); expected at most \
                 {MAX_DESIGNS}: fewer values along {key}, or fewer combinations",
                size.map_or_else(|| "too many".to_string(), |n| n.to_string()),
                numbers.len()
            )));
        }
        let designs = lattice.designs();
        let combos = combos_of(&lattice.axes, axis);
        Ok(Lattice {
            plan: lattice,
            axis,
            lo,
            hi,
            grid_values: numbers.len(),
            log,
            designs,
            combos,
        })
    }

    /// The lattice's size.
    pub fn len(&self) -> usize {
        self.plan.axes[self.axis].values.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The value at a (fractional) lattice index.
    pub fn x(&self, j: f64) -> f64 {
        at(self.lo, self.hi, self.log, j / (self.len() - 1) as f64)
    }

    /// The smallest lattice step in the axis's unit.
    pub fn spacing(&self) -> f64 {
        self.x(1.0) - self.lo
    }

    /// The searched axis.
    pub fn searched(&self) -> &Axis {
        &self.plan.axes[self.axis]
    }

    /// The design of combination `c` at lattice index `j`.
    pub fn design(&self, c: usize, j: usize) -> &Design {
        let mut index = 0;
        for (a, axis) in self.plan.axes.iter().enumerate() {
            let i = if a == self.axis { j } else { self.combos[c][a] };
            index = index * axis.values.len() + i;
        }
        &self.designs[index]
    }

    /// The other axes with two or more values and combination `c`'s value on each:
    /// (column, key, value).
    pub fn combo_values(&self, c: usize) -> Vec<(String, String, toml::Value)> {
        (self.plan.axes.iter().enumerate())
            .filter(|(a, axis)| *a != self.axis && axis.values.len() > 1)
            .map(|(a, axis)| {
                let v = axis.values[self.combos[c][a]].clone();
                (axis.column.clone(), axis.key.clone(), v)
            })
            .collect()
    }
}

/// The most designs a lattice holds (a sweep's grid may hold as many).
pub const MAX_DESIGNS: usize = 1_000_000;

/// Whether the base scene's `key` is a whole number (its TOML value an integer).
fn integer_key(plan: &Plan, key: &str) -> bool {
    let table = toml::Table::try_from(&plan.base_scene).unwrap_or_default();
    matches!(
        crate::scene::lookup(&table, key),
        Some(toml::Value::Integer(_))
    )
}

/// The value a fraction `t` of the way from `lo` to `hi`, evenly or in the logarithm.
fn at(lo: f64, hi: f64, log: bool, t: f64) -> f64 {
    if log {
        lo * (hi / lo).powf(t)
    } else {
        lo + (hi - lo) * t
    }
}

/// Every combination of the axes' value indices with `skip`'s held at 0, the last axis
/// fastest (the grid's order).
fn combos_of(axes: &[Axis], skip: usize) -> Vec<Vec<usize>> {
    let mut out = vec![vec![0; axes.len()]];
    for (a, axis) in axes.iter().enumerate() {
        if a == skip {
            continue;
        }
        out = out
            .into_iter()
            .flat_map(|c| {
                (0..axis.values.len()).map(move |i| {
                    let mut c = c.clone();
                    c[a] = i;
                    c
                })
            })
            .collect();
    }
    out
}

/// Rounds a computed lattice value to 10 significant digits (0.30000000000000004 → 0.3).
fn tidy(v: f64) -> f64 {
    format!("{v:.10e}").parse().unwrap_or(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan_of(text: &str) -> Plan {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        std::fs::write(&path, text).unwrap();
        Plan::load(&path, &[]).unwrap()
    }

    #[test]
    fn the_lattice_holds_the_grid_and_finds_each_design() {
        let plan = plan_of("[sweep]\nr = [4.0, 6.0, 8.0]\nrm = [5.0, 10.0]\nfriction = [0.2]\n");
        let l = Lattice::new(&plan, "r").unwrap();
        assert_eq!(l.len(), 2 * PER_STEP + 1);
        assert_eq!((l.lo, l.hi, l.grid_values), (4.0, 8.0, 3));
        assert_eq!(l.combos.len(), 2);
        assert!((l.spacing() - 0.25).abs() < 1e-12);
        // The grid's values are lattice values; each design is the one with those values.
        let d = l.design(1, PER_STEP);
        assert_eq!(d.values[0], toml::Value::Float(6.0));
        assert_eq!(d.values[1], toml::Value::Float(10.0));
        let grid = plan.designs();
        let same = grid.iter().find(|g| g.values == d.values).unwrap();
        assert_eq!(Design::values_hash(&same.id), Design::values_hash(&d.id));
        assert_eq!(l.combo_values(1)[0].0, "rm");
        assert_ne!(l.plan.sweep_hash, plan.sweep_hash);
        assert!(!l.log);
        // A pressure from 0.01 to 10 MPa: even in the logarithm, ends exact.
        let plan = plan_of("[sweep]\nholder_pressure = [0.01, 0.1, 1.0, 10.0]\n");
        let l = Lattice::new(&plan, "holder_pressure").unwrap();
        assert!(l.log);
        assert_eq!(l.len(), 3 * PER_STEP + 1);
        assert!((l.x(PER_STEP as f64) - 0.1).abs() < 1e-12);
        assert_eq!(l.searched().values[2 * PER_STEP], toml::Value::Float(1.0));
        assert_eq!(l.plan.base_hash, plan.base_hash);
    }

    #[test]
    fn an_axis_that_cannot_be_searched_is_refused_by_name() {
        let plan = plan_of("[sweep]\nr = [4.0, 6.0]\nfriction = [0.2]\n");
        for (key, must) in [
            (
                "rp",
                "not a swept key; expected one of the [sweep] table's: r, friction",
            ),
            ("friction", "expected two or more numbers"),
        ] {
            let e = Lattice::new(&plan, key).unwrap_err();
            assert!(e.is_bad_input());
            assert!(e.to_string().contains(must), "{e}");
            assert!(e.to_string().contains("s.toml"), "{e}");
        }
    }
}
