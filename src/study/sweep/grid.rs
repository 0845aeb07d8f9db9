//! The grid of a plan: its designs (ids, values), the results' parameter columns, and each
//! design's scene.

use super::plan::{Plan, SHORT_NAMES, parse_sets};
use super::values::{fnv_hex, show_value, toml_literal, unit_of};
use crate::scene::{Override, Scene, SceneError, ToolKind, lookup};

/// One design of the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    pub index: usize,
    /// `d007-3fa1c2`: the index and a hash of the parameter values.
    pub id: String,
    /// One value per axis.
    pub values: Vec<toml::Value>,
}

impl Design {
    /// The hash part of a design id (`3fa1c2` of `d007-3fa1c2`): the design's values, which
    /// stay when its number moves because the grid grew.
    pub fn values_hash(id: &str) -> Option<&str> {
        id.rsplit_once('-').map(|(_, h)| h)
    }
}

/// A parameter column of the results: a swept axis, or a short name held at the base value.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub name: String,
    pub key: String,
    pub axis: Option<usize>,
}

impl Plan {
    /// Every design, in grid order (the last axis varies fastest).
    pub fn designs(&self) -> Vec<Design> {
        let total = self.len();
        let width = (total.saturating_sub(1)).to_string().len().max(3);
        (0..total)
            .map(|index| {
                let mut rest = index;
                let mut values = vec![toml::Value::Boolean(false); self.axes.len()];
                for (a, axis) in self.axes.iter().enumerate().rev() {
                    let n = axis.values.len();
                    values[a] = axis.values[rest % n].clone();
                    rest /= n;
                }
                let canonical: Vec<String> = self
                    .axes
                    .iter()
                    .zip(&values)
                    .map(|(a, v)| format!("{}={}", a.key, show_value(v)))
                    .collect();
                let hash = fnv_hex(&canonical.join(";"));
                Design {
                    index,
                    id: format!("d{index:0width$}-{}", &hash[..6]),
                    values,
                }
            })
            .collect()
    }

    /// The parameter columns: the short names that apply to the base's punch (all five for a
    /// box) or are swept, then the other swept keys.
    pub fn columns(&self) -> Vec<Column> {
        let kind = self.base_scene.tools.kind;
        let mut cols = Vec::new();
        for (short, key) in SHORT_NAMES {
            let axis = self.axes.iter().position(|a| a.key == key);
            let applies = match kind {
                ToolKind::Box => true,
                // A mesh tool's radii are in its STL.
                ToolKind::Mesh => !matches!(short, "r" | "rp" | "rm"),
                _ => !matches!(short, "r" | "rp"),
            };
            if axis.is_some() || applies {
                cols.push(Column {
                    name: short.to_string(),
                    key: key.to_string(),
                    axis,
                });
            }
        }
        for (i, a) in self.axes.iter().enumerate() {
            if !SHORT_NAMES.iter().any(|(_, k)| *k == a.key) {
                cols.push(Column {
                    name: a.column.clone(),
                    key: a.key.clone(),
                    axis: Some(i),
                });
            }
        }
        cols
    }

    /// The `--set` overrides of the base, parsed.
    fn base_overrides(&self) -> Vec<Override> {
        parse_sets(&self.set).unwrap_or_default()
    }

    /// The design's scene, or why it breaks a bound (the detail starts with the key).
    pub fn design_scene(&self, design: &Design) -> Result<Scene, SceneError> {
        let mut sets = self.base_overrides();
        for (axis, v) in self.axes.iter().zip(&design.values) {
            let literal = toml_literal(v);
            sets.push(Override {
                key: axis.key.clone(),
                value: v.clone(),
                text: format!("{}={literal}", axis.key),
            });
        }
        Scene::from_toml_str(&self.base_text, &self.base_origin, &sets)
    }

    /// The design's row parameters, in column order.
    pub fn params(&self, columns: &[Column], design: &Design) -> Vec<(String, toml::Value)> {
        let table = toml::Table::try_from(&self.base_scene).unwrap_or_default();
        columns
            .iter()
            .map(|c| {
                let v = match c.axis {
                    Some(a) => design.values[a].clone(),
                    None => lookup(&table, &c.key)
                        .cloned()
                        .unwrap_or(toml::Value::String(String::new())),
                };
                (c.name.clone(), v)
            })
            .collect()
    }

    /// The swept parameters of a design in words, a line for the radii and one for the rest:
    /// `["r 5, rp 6, rm 5 mm", "friction 0.2, holder_pressure 1 MPa"]`. Axes with a single value
    /// are left out (they are the same for every design).
    pub fn label_lines(&self, design: &Design) -> Vec<String> {
        let mut radii = Vec::new();
        let mut rest = Vec::new();
        for (a, v) in self.axes.iter().zip(&design.values) {
            if a.values.len() < 2 {
                continue;
            }
            let name = a.column.rsplit('.').next().unwrap_or(&a.column);
            if matches!(a.column.as_str(), "r" | "rp" | "rm") {
                radii.push(format!("{name} {}", show_value(v)));
            } else {
                rest.push(format!("{name} {}{}", show_value(v), unit_of(&a.key)));
            }
        }
        let mut lines = Vec::new();
        if !radii.is_empty() {
            lines.push(format!("{} mm", radii.join(", ")));
        }
        if !rest.is_empty() {
            lines.push(rest.join(", "));
        }
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::super::plan::tests::plan_of;

    #[test]
    fn designs_out_of_bounds_are_invalid_with_the_reason() {
        let p = plan_of("[sweep]\nr = [5.0, 40.0]\n").unwrap();
        let d = p.designs();
        assert!(p.design_scene(&d[0]).is_ok());
        let why = p.design_scene(&d[1]).unwrap_err().detail;
        assert!(why.starts_with("tools.r = 40"), "{why}");
    }
}
