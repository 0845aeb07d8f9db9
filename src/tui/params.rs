//! The explorer's parameters: the ranges of the swept scene keys, the locking angle and the
//! accuracy level, as text the user edits, checked against the scene's bounds as they type,
//! and turned into a sweep plan.

use std::path::PathBuf;

use crate::accuracy::Accuracy;
use crate::presets;
use crate::scene::{Override, Scene};
use crate::study::sweep::{Plan, show_value, unit_of};
use crate::verdict::Limits;

use super::error::ParamError;

/// At most this many designs are run from the explorer (the headless sweep takes more).
pub const MAX_DESIGNS: usize = 2000;

/// The sweep document the explorer starts from: a sweep file, or the embedded default.
#[derive(Clone, Debug)]
pub struct Source {
    /// Names the document in errors and places a relative `base` file.
    pub path: PathBuf,
    /// What the title bar calls it.
    pub title: String,
    pub doc: toml::Table,
    /// Whether it is the embedded default, whose `base` the binary carries (a user's sweep
    /// reads its `base` from the disk, whatever its name).
    pub embedded: bool,
}

impl Source {
    /// The plan of `doc` (this source's document, edited) with `overrides` over its base
    /// scene. A plan keeps its overrides as `--set` text (its `sweep.lock` and `results.json`
    /// record them): the text of each is made here, once, from its typed value.
    fn plan(&self, doc: &toml::Table, overrides: &[Override]) -> Result<Plan, ParamError> {
        let sets: Vec<String> = overrides.iter().map(|o| o.text.clone()).collect();
        let plan = if self.embedded {
            crate::study::sweep::embedded::plan(&self.path, doc, &sets)
        } else {
            Plan::from_document(&self.path, doc, &sets)
        };
        plan.map_err(|e| ParamError::Plan(e.to_string()))
    }
}

/// The embedded default, `presets/paper-box-explorer.toml`: the paper's square box (the
/// open-box preset as the base scene) with the paper's tight and open radii, friction 0.2,
/// holder pressure 1 MPa: 8 designs.
pub fn default_source() -> Source {
    Source {
        path: PathBuf::from(presets::EXPLORER_NAME),
        title: "paper box (default)".into(),
        doc: presets::explorer_document(),
        embedded: true,
    }
}

/// What a parameter line edits.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// A swept scene key: its column name in the results and its dotted key.
    Axis {
        column: String,
        key: String,
    },
    LockingAngle,
    /// The yarns' break tension, N.
    BreakTension,
    Accuracy,
}

/// One line of the parameters panel.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub target: Target,
    /// The label shown (the column's short name).
    pub label: String,
    pub unit: &'static str,
    /// The committed text (always valid).
    pub text: String,
}

/// The parameters as edited, and the plan they make.
#[derive(Clone, Debug)]
pub struct Parameters {
    pub source: Source,
    pub fields: Vec<Field>,
    /// The locking angle and the break tension set over the base scene.
    pub limits: Limits,
    pub accuracy: Accuracy,
    /// The plan of the committed fields.
    pub plan: Plan,
}

/// `start..stop/count` → the values, both ends included.
fn range_values(text: &str) -> Option<Result<Vec<f64>, ParamError>> {
    let (span, count) = text.split_once('/')?;
    let (a, b) = span.split_once("..")?;
    let parse = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    Some(match (parse(a), parse(b), count.trim().parse::<usize>()) {
        (Some(a), Some(b), Ok(n)) if (1..=MAX_DESIGNS).contains(&n) => Ok((0..n)
            .map(|i| {
                let v = if n == 1 {
                    a
                } else {
                    a + (b - a) * i as f64 / (n - 1) as f64
                };
                format!("{v:.10e}").parse().unwrap_or(v)
            })
            .collect()),
        _ => Err(ParamError::Text(format!(
            "{text:?}: a range is start..stop/count, e.g. 5..10/3 (count 1 to {MAX_DESIGNS})"
        ))),
    })
}

/// Reads a list of values typed by the user: `5, 7.5, 10`, or a range `5..10/3`.
pub fn parse_list(text: &str, base: &toml::Value) -> Result<Vec<toml::Value>, ParamError> {
    let t = text.trim();
    if t.is_empty() {
        return Err(ParamError::Text(
            "empty: expected one value or more, e.g. 5, 7.5, 10 or 5..10/3".into(),
        ));
    }
    if let Some(range) = range_values(t) {
        return range.map(|v| v.into_iter().map(toml::Value::Float).collect());
    }
    if let toml::Value::String(_) = base {
        return word_list(t);
    }
    let doc: toml::Table = format!("v = [{t}]").parse().map_err(|_| {
        ParamError::Text(format!(
            "{t:?}: expected values separated by commas, e.g. 5, 7.5, 10 or 5..10/3"
        ))
    })?;
    let Some(toml::Value::Array(values)) = doc.get("v") else {
        return Err(ParamError::Text(format!(
            "{t:?}: expected a list of values"
        )));
    };
    let numeric = matches!(base, toml::Value::Float(_) | toml::Value::Integer(_));
    let wrong = |message: String| Err(ParamError::Text(message));
    values
        .iter()
        .map(|v| match (v, base) {
            (toml::Value::Integer(i), toml::Value::Float(_)) => Ok(toml::Value::Float(*i as f64)),
            (toml::Value::Float(f), _) if !f.is_finite() => {
                wrong(format!("{f}: expected a finite number"))
            }
            (toml::Value::Float(_) | toml::Value::Integer(_), _) if numeric => Ok(v.clone()),
            _ if numeric => wrong(format!("{}: expected a number", show_value(v))),
            _ if std::mem::discriminant(v) == std::mem::discriminant(base) => Ok(v.clone()),
            _ => wrong(format!(
                "{}: expected a value like {}",
                show_value(v),
                show_value(base)
            )),
        })
        .collect()
}

/// Words typed for a key whose values are words (`auto, full`; quotes may be typed too).
fn word_list(text: &str) -> Result<Vec<toml::Value>, ParamError> {
    text.split(',')
        .map(|w| {
            let w = w.trim();
            let bare = (w.strip_prefix('"').and_then(|w| w.strip_suffix('"'))).unwrap_or(w);
            if bare.is_empty() || bare.contains('"') {
                Err(ParamError::Text(format!(
                    "{text:?}: expected words separated by commas, e.g. auto, full"
                )))
            } else {
                Ok(toml::Value::String(bare.to_string()))
            }
        })
        .collect()
}

/// The scene keys of the fabric's locking angle and of the yarns' break tension.
const LOCKING_KEY: &str = "fabric.locking_angle_deg";
const BREAK_KEY: &str = "fabric.break_tension_n";
/// The scene key an accuracy level sets (as [`Accuracy::overrides`] does).
const MESH_KEY: &str = "mesh.element_size";

/// A number set over the base scene at `key`, held as its TOML value; its text is the
/// `--set` a user would write (`fabric.locking_angle_deg=60.0`).
fn number_override(key: &str, value: f64) -> Override {
    Override {
        key: key.to_string(),
        value: toml::Value::Float(value),
        text: format!("{key}={value:?}"),
    }
}

/// A limit typed by the user: a finite number, or what was expected.
fn limit_value(text: &str, expected: &str) -> Result<f64, ParamError> {
    text.trim()
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| ParamError::Text(format!("{:?}: expected {expected}", text.trim())))
}

fn list_text(values: &[toml::Value]) -> String {
    values.iter().map(show_value).collect::<Vec<_>>().join(", ")
}

impl Parameters {
    /// The parameters of a sweep document: its axes, and the scene's other sweepable keys at
    /// their base values.
    pub fn new(source: Source) -> Result<Parameters, ParamError> {
        let plan = source.plan(&source.doc, &[])?;
        let limits = Limits::of(&plan.base_scene);
        let h = plan.base_scene.mesh.element_size;
        // The level nearest the scene's own mesh.
        let accuracy = Accuracy::ALL
            .into_iter()
            .min_by(|a, b| {
                let d = |x: &Accuracy| (x.element_size_mm() / h).ln().abs();
                d(a).total_cmp(&d(b))
            })
            .unwrap_or(Accuracy::Standard);
        let mut fields: Vec<Field> = plan
            .columns()
            .into_iter()
            .map(|c| {
                let values = match c.axis {
                    Some(a) => plan.axes[a].values.clone(),
                    None => plan
                        .designs()
                        .first()
                        .map(|d| {
                            plan.params(std::slice::from_ref(&c), d)
                                .into_iter()
                                .map(|(_, v)| v)
                                .collect()
                        })
                        .unwrap_or_default(),
                };
                Field {
                    label: c.name.rsplit('.').next().unwrap_or(&c.name).into(),
                    unit: unit_of(&c.key),
                    text: list_text(&values),
                    target: Target::Axis {
                        column: c.name,
                        key: c.key,
                    },
                }
            })
            .collect();
        fields.push(Field {
            target: Target::LockingAngle,
            label: "locking".into(),
            unit: "°",
            text: crate::show::Num(limits.locking_angle_deg).to_string(),
        });
        // The break tension is a limit, like the locking angle, unless the sweep varies it.
        if !plan.axes.iter().any(|a| a.key == BREAK_KEY) {
            fields.push(Field {
                target: Target::BreakTension,
                label: "break".into(),
                unit: "N",
                text: crate::show::Num(limits.break_tension_n).to_string(),
            });
        }
        fields.push(Field {
            target: Target::Accuracy,
            label: "accuracy".into(),
            unit: "",
            text: accuracy.name().into(),
        });
        let mut p = Parameters {
            source,
            fields,
            limits,
            accuracy,
            plan,
        };
        p.plan = p.build()?;
        Ok(p)
    }

    /// The overrides of the base scene, typed: the locking angle, the break tension (unless
    /// swept) and the accuracy level's mesh.
    fn overrides(&self) -> Vec<Override> {
        let mut sets = vec![number_override(LOCKING_KEY, self.limits.locking_angle_deg)];
        if self.fields.iter().any(|f| f.target == Target::BreakTension) {
            sets.push(number_override(BREAK_KEY, self.limits.break_tension_n));
        }
        sets.push(number_override(MESH_KEY, self.accuracy.element_size_mm()));
        sets
    }

    /// The plan of the committed fields.
    fn build(&self) -> Result<Plan, ParamError> {
        let mut doc = self.source.doc.clone();
        let mut sweep = toml::Table::new();
        for f in &self.fields {
            if let Target::Axis { column, key } = &f.target {
                let base = self.base_value(key);
                let values = parse_list(&f.text, &base).map_err(|e| {
                    ParamError::Plan(format!(
                        "{}: [sweep] {column}: {e}",
                        self.source.path.display()
                    ))
                })?;
                sweep.insert(column.clone(), toml::Value::Array(values));
            }
        }
        doc.insert("sweep".into(), toml::Value::Table(sweep));
        self.source.plan(&doc, &self.overrides())
    }

    /// The base scene's value of a key (what the typed values must look like).
    fn base_value(&self, key: &str) -> toml::Value {
        let table = toml::Table::try_from(&self.plan.base_scene).unwrap_or_default();
        crate::scene::lookup(&table, key)
            .cloned()
            .unwrap_or(toml::Value::Float(0.0))
    }

    /// Whether the base scene with `key = value` over it keeps its bounds: the scene's
    /// message (which names the key) when it does not.
    fn check_value(&self, key: &str, value: &toml::Value) -> Result<(), ParamError> {
        let mut sets = self.overrides();
        sets.push(Override {
            key: key.to_string(),
            value: value.clone(),
            text: format!("{key}={}", show_value(value)),
        });
        Scene::from_toml_str(&self.plan.base_text, &self.plan.base_origin, &sets)
            .map(|_| ())
            .map_err(|e| ParamError::Scene(e.detail))
    }

    /// Checks the text typed into field `index` (as the user types): what is wrong with it,
    /// naming the value and what was expected.
    pub fn check(&self, index: usize, text: &str) -> Result<(), ParamError> {
        let Some(field) = self.fields.get(index) else {
            return Err(ParamError::Text("no such parameter".into()));
        };
        match &field.target {
            Target::Accuracy => Accuracy::parse(text)
                .map(|_| ())
                .map_err(|e| ParamError::Text(e.to_string())),
            Target::LockingAngle => {
                let v = limit_value(text, "the locking angle in degrees, e.g. 60")?;
                self.check_value(LOCKING_KEY, &toml::Value::Float(v))
            }
            Target::BreakTension => {
                let v = limit_value(text, "the break tension in N, e.g. 1500")?;
                self.check_value(BREAK_KEY, &toml::Value::Float(v))
            }
            Target::Axis { key, .. } => {
                let values = parse_list(text, &self.base_value(key))?;
                for v in &values {
                    self.check_value(key, v)?;
                }
                let others: usize = self
                    .fields
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| *i != index)
                    .filter_map(|(_, f)| match &f.target {
                        Target::Axis { key, .. } => parse_list(&f.text, &self.base_value(key))
                            .ok()
                            .map(|v| v.len()),
                        _ => None,
                    })
                    .product();
                let total = others.saturating_mul(values.len());
                if total > MAX_DESIGNS {
                    return Err(ParamError::Text(format!(
                        "{total} designs: the explorer runs at most {MAX_DESIGNS}; use `wovenform sweep` for more"
                    )));
                }
                // What only the whole plan sees (a value given twice, a pair of keys that
                // cannot go together): as Enter would find it.
                let mut edited = self.clone();
                edited.fields[index].text = text.to_string();
                edited.build().map(|_| ())
            }
        }
    }

    /// Commits the text of field `index` when it checks; the plan follows.
    pub fn commit(&mut self, index: usize, text: &str) -> Result<(), ParamError> {
        self.check(index, text)?;
        let old = self.clone();
        let field = &mut self.fields[index];
        match field.target {
            Target::Accuracy => {
                self.accuracy =
                    Accuracy::parse(text).map_err(|e| ParamError::Text(e.to_string()))?;
                field.text = self.accuracy.name().into();
            }
            Target::LockingAngle => {
                self.limits.locking_angle_deg = limit_value(text, "a number")?;
                field.text = crate::show::Num(self.limits.locking_angle_deg).to_string();
            }
            Target::BreakTension => {
                self.limits.break_tension_n = limit_value(text, "a number")?;
                field.text = crate::show::Num(self.limits.break_tension_n).to_string();
            }
            Target::Axis { ref key, .. } => {
                let base = old.base_value(key);
                field.text = list_text(&parse_list(text, &base)?);
            }
        }
        match self.build() {
            Ok(plan) => {
                self.plan = plan;
                Ok(())
            }
            Err(e) => {
                *self = old;
                Err(e)
            }
        }
    }

    /// Sets the accuracy level (and the plan with it).
    pub fn set_accuracy(&mut self, level: Accuracy) {
        while self.accuracy != level {
            let before = self.accuracy;
            self.step_accuracy(level.element_size_mm() < self.accuracy.element_size_mm());
            if self.accuracy == before {
                break;
            }
        }
    }

    /// The accuracy level one step up or down.
    pub fn step_accuracy(&mut self, up: bool) {
        let next = self.accuracy.step(up);
        if let Some(i) = self
            .fields
            .iter()
            .position(|f| f.target == Target::Accuracy)
        {
            let _ = self.commit(i, next.name());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_and_ranges_are_read() {
        let f = toml::Value::Float(1.0);
        assert_eq!(
            parse_list("5, 7.5,10", &f).unwrap(),
            [5.0, 7.5, 10.0].map(toml::Value::Float)
        );
        assert_eq!(
            parse_list("5..10/3", &f).unwrap(),
            [5.0, 7.5, 10.0].map(toml::Value::Float)
        );
        assert!(
            parse_list("5..10/0", &f)
                .unwrap_err()
                .to_string()
                .contains("start..stop/count")
        );
        assert!(
            parse_list("5, x", &f)
                .unwrap_err()
                .to_string()
                .contains("separated by commas")
        );
        assert!(
            parse_list("", &f)
                .unwrap_err()
                .to_string()
                .contains("empty")
        );
        assert!(
            parse_list("true", &f)
                .unwrap_err()
                .to_string()
                .contains("expected a number")
        );
    }

    #[test]
    fn a_sweep_of_words_opens_and_what_the_plan_refuses_is_shown_before_enter() {
        let word = toml::Value::String("auto".into());
        let words = parse_list("auto, \"full\"", &word).unwrap();
        let expected = ["auto", "full"].map(|w| toml::Value::String(w.into()));
        assert_eq!(words, expected);
        assert!(parse_list("auto,, full", &word).is_err());
        // A sweep file that `sweep` runs, over a key of words, opens with its axis.
        let doc: toml::Table =
            "base = \"paper-box-open.toml\"\n[sweep]\nr = [5.0, 10.0]\n\"mesh.symmetry\" = [\"auto\", \"full\"]\n"
                .parse()
                .unwrap();
        let source = Source {
            path: PathBuf::from("presets/words.toml"),
            title: "words".into(),
            doc,
            embedded: false,
        };
        let mut p = Parameters::new(source).unwrap();
        assert_eq!(p.plan.designs().len(), 4);
        let symmetry = p.fields.iter().position(|f| f.label == "symmetry").unwrap();
        assert!(p.check(symmetry, "full").is_ok());
        // A value typed twice is refused as the user types, as Enter would refuse it.
        let r = p.fields.iter().position(|f| f.label == "r").unwrap();
        let e = p.check(r, "4, 4").unwrap_err().to_string();
        assert!(e.contains("is given twice"), "{e}");
        assert!(p.commit(r, "4, 4").is_err());
        assert!(p.commit(symmetry, "full").is_ok());
        assert_eq!(p.plan.designs().len(), 2);
    }

    #[test]
    fn the_default_shows_the_box_parameters_and_checks_bounds() {
        let p = Parameters::new(default_source()).unwrap();
        let labels: Vec<&str> = p.fields.iter().map(|f| f.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "r",
                "rp",
                "rm",
                "friction",
                "holder_pressure",
                "locking",
                "break",
                "accuracy"
            ]
        );
        assert_eq!(p.plan.len(), 8);
        assert_eq!(p.fields[0].text, "5, 10");
        let err = p.check(0, "-1").unwrap_err().to_string();
        assert!(err.contains("tools.r"), "{err}");
        assert!(p.check(3, "0.1, 0.3").is_ok());
        assert!(
            p.check(3, "1.5")
                .unwrap_err()
                .to_string()
                .contains("process.friction")
        );
        assert!(
            p.check(7, "fast")
                .unwrap_err()
                .to_string()
                .contains("coarse, standard or fine")
        );
    }

    #[test]
    fn commits_change_the_plan() {
        let mut p = Parameters::new(default_source()).unwrap();
        p.commit(3, "0.1..0.3/3").unwrap();
        assert_eq!(p.plan.len(), 24);
        assert_eq!(p.fields[3].text, "0.1, 0.2, 0.3");
        p.commit(5, "55").unwrap();
        assert_eq!(p.plan.base_scene.fabric.locking_angle_deg, 55.0);
        p.step_accuracy(false);
        assert_eq!(p.plan.base_scene.mesh.element_size, 5.0);
        assert!(p.commit(0, "-3").is_err());
        assert_eq!(p.fields[0].text, "5, 10");
    }

    #[test]
    fn the_limits_go_to_the_plan_as_typed_values() {
        let mut p = Parameters::new(default_source()).unwrap();
        let locking = 0.1 + 0.2 + 55.0;
        p.limits.locking_angle_deg = locking;
        p.limits.break_tension_n = 1234.5;
        let plan = p.build().unwrap();
        assert_eq!(plan.base_scene.fabric.locking_angle_deg, locking);
        assert_eq!(Limits::of(&plan.base_scene), p.limits);
        // The plan records them as the --set a user would write.
        assert_eq!(
            plan.set,
            [
                format!("fabric.locking_angle_deg={locking:?}"),
                "fabric.break_tension_n=1234.5".to_string(),
                "mesh.element_size=2.5".to_string(),
            ]
        );
        let o = &p.overrides()[0];
        assert_eq!(
            (o.key.as_str(), &o.value),
            (LOCKING_KEY, &toml::Value::Float(locking))
        );
    }
}
