//! `--set KEY=VALUE` overrides, applied to the scene's TOML table before it is typed, and the
//! errors of typing that table (unknown keys, wrong types), each blamed on the file or on the
//! `--set` that brought the key in.

use std::str::FromStr;

use super::SceneError;
use super::keys::{is_dotted_key, lookup};

/// One `--set KEY=VALUE` override; VALUE is a TOML literal.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// Dotted key, e.g. `fabric.l0`.
    pub key: String,
    pub value: toml::Value,
    /// The text as given, for error messages: line breaks written `\n`, and a long one cut
    /// to its first characters (see `excerpt`).
    pub text: String,
}

impl FromStr for Override {
    type Err = SceneError;

    fn from_str(text: &str) -> Result<Self, SceneError> {
        let shown = excerpt(&text.replace('\n', "\\n").replace('\r', "\\r"));
        let origin = format!("--set {shown}");
        let err = |key: Option<String>, detail: String| SceneError {
            origin: origin.clone(),
            key,
            detail,
        };
        if text.contains(['\n', '\r']) {
            return Err(err(
                None,
                "one KEY=VALUE per --set, on one line: this one holds a line break (give each key \
                 its own --set)"
                    .into(),
            ));
        }
        let Some((key, value)) = text.split_once('=') else {
            return Err(err(
                None,
                "expected KEY=VALUE with VALUE a TOML literal, e.g. fabric.a=0.05".into(),
            ));
        };
        let key = key.trim();
        if !is_dotted_key(key) {
            return Err(err(
                None,
                format!(
                    "`{}` is not a key: expected a dotted key such as fabric.a",
                    excerpt(key)
                ),
            ));
        }
        let doc = format!("v = {}", value.trim());
        let value = doc
            .parse::<toml::Table>()
            .ok()
            .filter(|t| t.len() == 1)
            .and_then(|mut t| t.remove("v"))
            .ok_or_else(|| {
                let v = value.trim();
                let digits = v.trim_start_matches(['+', '-']);
                let expected = if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
                    "expected a whole number from −2⁶³ to 2⁶³ − 1 = 9223372036854775807 (the \
                     largest TOML takes)"
                } else {
                    "expected a TOML literal (a number, true/false, [a, b], or a \"quoted string\")"
                };
                err(
                    Some(key.to_string()),
                    format!("{key} = {}: {expected}", excerpt(v)),
                )
            })?;
        Ok(Override {
            key: key.to_string(),
            value,
            text: shown,
        })
    }
}

/// The longest text a message quotes from the user, characters.
const EXCERPT_CHARS: usize = 80;

/// `text` as a message quotes it: whole when short, else its first characters and its length
/// (a 100 kB value is not echoed back).
pub fn excerpt(text: &str) -> String {
    let count = text.chars().count();
    if count <= EXCERPT_CHARS {
        return text.to_string();
    }
    let head: String = text.chars().take(EXCERPT_CHARS - 20).collect();
    format!("{head}… ({count} characters)")
}

/// A message from a library that may quote a user's long value: whole up to 4 lines' worth,
/// else cut as [`excerpt`] does.
fn excerpt_long(text: &str) -> String {
    if text.chars().count() <= 4 * EXCERPT_CHARS {
        text.to_string()
    } else {
        excerpt(text)
    }
}

/// Who set the keys: the last override that `touches` any of them, else `origin` (the file,
/// or [`super::DEFAULT_ORIGIN`]). Shown as `--set KEY=VALUE`.
pub fn blame(overrides: &[Override], origin: &str, keys: &[&str]) -> String {
    overrides
        .iter()
        .rev()
        .find(|o| keys.iter().any(|k| touches(&o.key, k)))
        .map(|o| format!("--set {}", o.text))
        .unwrap_or_else(|| origin.to_string())
}

/// Whether an override of `set` touches `key` (a dotted key, or a serde path such as
/// `fabric.l0[1]`): it is the key, a table holding it, the array holding it, or a key inside
/// it (an override of `nosuch.key` brings in the unknown section `nosuch`).
fn touches(set: &str, key: &str) -> bool {
    let below = |inner: &str, outer: &str, marks: &[char]| {
        inner
            .strip_prefix(outer)
            .is_some_and(|rest| rest.starts_with(marks))
    };
    set == key || below(key, set, &['.', '[']) || below(set, key, &['.'])
}

/// Writes each quoted dotted key of `table` (`"process.stroke" = 12.0`, the spelling a
/// `[sweep]` table takes) as the nested key it names (`[process] stroke = 12.0`), at every
/// level; the key when it is also given the other way (`Err` holds it).
pub fn expand_dotted_keys(table: &mut toml::Table) -> Result<(), String> {
    let dotted: Vec<String> = (table.keys())
        .filter(|k| k.contains('.') && is_dotted_key(k))
        .cloned()
        .collect();
    for key in dotted {
        let value = table.remove(&key).expect("a key of the table");
        let parts: Vec<&str> = key.split('.').collect();
        let (last, parents) = parts.split_last().expect("a dotted key has parts");
        let mut t = &mut *table;
        for p in parents {
            let entry = t
                .entry(p.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            match entry {
                toml::Value::Table(inner) => t = inner,
                _ => return Err(key),
            }
        }
        if t.insert(last.to_string(), value).is_some() {
            return Err(key);
        }
    }
    for (_, value) in table.iter_mut() {
        if let toml::Value::Table(inner) = value {
            expand_dotted_keys(inner)?;
        }
    }
    Ok(())
}

/// Sets `o.key` in the table, creating intermediate tables as needed.
pub(super) fn apply_override(table: &mut toml::Table, o: &Override) -> Result<(), SceneError> {
    let parts: Vec<&str> = o.key.split('.').collect();
    let (last, parents) = parts.split_last().expect("a key has at least one part");
    let mut t = table;
    for (i, p) in parents.iter().enumerate() {
        let entry = t
            .entry(p.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        t = match entry {
            toml::Value::Table(inner) => inner,
            _ => {
                let at = parts[..=i].join(".");
                return Err(SceneError {
                    origin: format!("--set {}", o.text),
                    key: Some(o.key.clone()),
                    detail: format!("{at} is a value, not a table, so it has no key {}", o.key),
                });
            }
        };
    }
    // A table (`--set 'process={stroke=3}'`) sets its keys over the file's, as one --set each
    // would: it never drops the keys it does not name.
    match (t.get_mut(*last), &o.value) {
        (Some(toml::Value::Table(old)), toml::Value::Table(new)) => merge_tables(old, new),
        _ => {
            t.insert(last.to_string(), o.value.clone());
        }
    }
    Ok(())
}

/// Deep merge: `over`'s keys replace `base`'s, tables merged key by key (a `--set` table, a
/// sweep's inline `[scene]` over its base file).
pub fn merge_tables(base: &mut toml::Table, over: &toml::Table) {
    for (k, v) in over {
        match (base.get_mut(k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge_tables(b, o),
            _ => {
                base.insert(k.clone(), v.clone());
            }
        }
    }
}

/// Turns a serde error at `path` into a message naming the key and the expectation.
pub(super) fn structural_error(
    path: &str,
    message: &str,
    table: &toml::Table,
    origin_of: &dyn Fn(&str) -> String,
) -> SceneError {
    // serde: "unknown field `x`, expected one of `a`, `b`" (path = the table, or the key itself).
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let (name, expected) = rest.split_once('`').unwrap_or((rest, ""));
        let key = if path == "." || path.is_empty() {
            name.to_string()
        } else if path.ends_with(name) {
            path.to_string()
        } else {
            format!("{path}.{name}")
        };
        let expected = expected
            .trim_start_matches(", ")
            .replace("expected one of", "expected one of:")
            .replace("expected nothing", "expected no keys here")
            .replace('`', "");
        let section = if key.contains('.') { "key" } else { "section" };
        return SceneError {
            origin: origin_of(&key),
            detail: format!("{}: unknown {section}; {expected}", excerpt(&key)),
            key: Some(key),
        };
    }
    let shown = lookup(table, path)
        .map(|v| format!(" = {}", excerpt(&v.to_string())))
        .unwrap_or_default();
    // serde's message may quote the value too.
    let message = length_message(path, message).unwrap_or_else(|| excerpt_long(message));
    SceneError {
        origin: origin_of(path),
        detail: format!("{}{shown}: {message}", excerpt(path)),
        key: Some(path.to_string()),
    }
}

/// serde's "invalid length 3, expected fewer elements in array" for a key of a fixed number
/// of values, said as what the key takes: "3 values: expected 2 numbers ([B1, B2]…)".
fn length_message(path: &str, message: &str) -> Option<String> {
    let given = message.strip_prefix("invalid length ")?.split(',').next()?;
    let shape = super::keys::unset_key_shape(path).or_else(|| {
        let defaults = toml::Table::try_from(super::Scene::default()).ok()?;
        lookup(&defaults, path).cloned()
    });
    let n = match shape {
        Some(toml::Value::Array(values)) => values.len(),
        // A key of another kind of tool than the default's: serde says the length.
        _ => message.split("of length ").nth(1)?.trim().parse().ok()?,
    };
    let word = ["no", "one", "two", "three", "four"]
        .get(n)
        .copied()
        .unwrap_or("several");
    let names = match path {
        "fabric.bending_rigidity" => "[B1, B2] in N·mm".to_string(),
        "fabric.compressive_stiffness" => "[Cc1, Cc2] in N".to_string(),
        "fabric.shear_moment" => "[k1, k3, k5] in N·mm/mm²".to_string(),
        "tools.axes" => "[ax, ay, az] in mm".to_string(),
        _ => format!("[{}]", vec!["x"; n].join(", ")),
    };
    Some(format!(
        "{given} values: expected {word} numbers in brackets, {names}"
    ))
}

#[cfg(test)]
mod tests {
    use super::super::parse;
    use super::*;

    #[test]
    fn a_list_of_the_wrong_length_says_how_many_values_the_key_takes() {
        let e = parse("", &["fabric.bending_rigidity=[0.1,0.1,0.1]"]).unwrap_err();
        assert!(e.origin.starts_with("--set fabric.bending_rigidity"), "{e}");
        assert!(
            e.detail
                .ends_with("3 values: expected two numbers in brackets, [B1, B2] in N·mm"),
            "{e}"
        );
        let e = parse("[tools]\nkind = \"ellipsoid\"\naxes = [1.0, 2.0]\n", &[]).unwrap_err();
        assert!(e.detail.contains("expected three numbers"), "{e}");
    }

    #[test]
    fn a_table_sets_its_keys_and_keeps_the_files_others() {
        let file = "[process]\nfriction = 0.4\nholder_pressure = 3.0\n";
        let s = parse(file, &["process={stroke=3.0}"]).unwrap();
        assert_eq!(s.process.stroke, 3.0);
        assert_eq!(s.process.friction, 0.4);
        assert_eq!(s.process.holder_pressure, 3.0);
    }

    #[test]
    fn overrides_apply_in_order() {
        let s = parse(
            "[fabric]\na = 0.05\n",
            &["fabric.a=0.06", "fabric.l0=[5.0,4.0]"],
        )
        .unwrap();
        assert_eq!(s.fabric.a, 0.06);
        assert_eq!(s.fabric.l0.0, [5.0, 4.0]);
        assert!("fabric.a".parse::<Override>().is_err());
        assert!("fabric.a=abc".parse::<Override>().is_err());
        let e = parse("[fabric]\na = 0.05\n", &["fabric.a.x=1"]).unwrap_err();
        assert!(e.detail.contains("not a table"), "{e}");
    }

    #[test]
    fn the_last_override_of_a_key_is_blamed() {
        let sets: Vec<Override> = ["tools.r=1", "tools=2", "tools.r=3"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        assert_eq!(blame(&sets, "x.toml", &["tools.r"]), "--set tools.r=3");
        assert_eq!(blame(&sets, "x.toml", &["tools.rp"]), "--set tools=2");
        assert_eq!(blame(&sets, "x.toml", &["fabric.a"]), "x.toml");
        assert_eq!(
            blame(&sets[..1], "x.toml", &["tools.side", "tools.r"]),
            "--set tools.r=1"
        );
        assert_eq!(blame(&sets, "x.toml", &["tool"]), "x.toml");
    }

    #[test]
    fn an_override_touches_its_key_the_tables_around_it_and_what_is_inside() {
        for (set, key) in [
            ("fabric.l0", "fabric.l0"),
            ("fabric", "fabric.l0"),
            ("fabric.l0", "fabric.l0[1]"),
            ("nosuch.key", "nosuch"),
            ("tools.r.x", "tools.r"),
        ] {
            assert!(touches(set, key), "{set} → {key}");
        }
        for (set, key) in [
            ("fabric.l0", "fabric.l"),
            ("fabric.l", "fabric.l0"),
            ("tools.r", "tools.rp"),
            ("tools.rp", "tools.r"),
            ("fabric.l0[1]", "fabric.l0"),
        ] {
            assert!(!touches(set, key), "{set} → {key}");
        }
    }

    #[test]
    fn unknown_keys_are_named() {
        let e = parse("[fabric]\nfoo = 1\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("fabric.foo"), "{e}");
        assert!(
            e.to_string().starts_with("x.toml: fabric.foo: unknown key"),
            "{e}"
        );
        let e = parse("[tooling]\nr = 1\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("tooling"), "{e}");
        let e = parse("", &["fabric.bar=2"]).unwrap_err();
        assert_eq!(e.origin, "--set fabric.bar=2");
        assert!(e.detail.contains("fabric.bar"), "{e}");
        // An unknown section that only a --set brings in is blamed on it, not on the file.
        let e = parse("[fabric]\na = 0.05\n", &["nosuch.key=1"]).unwrap_err();
        assert_eq!(e.origin, "--set nosuch.key=1");
        assert_eq!(e.key.as_deref(), Some("nosuch"), "{e}");
    }

    #[test]
    fn wrong_types_are_named() {
        let e = parse("[fabric]\nundulation = 3\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("fabric.undulation"), "{e}");
        assert!(e.detail.contains("= 3"), "{e}");
        // A wrong element of an array given with --set: the --set is blamed.
        let e = parse("", &["fabric.l0=[1,\"x\"]"]).unwrap_err();
        assert_eq!(e.origin, "--set fabric.l0=[1,\"x\"]", "{e}");
        assert_eq!(e.key.as_deref(), Some("fabric.l0[1]"), "{e}");
    }

    #[test]
    fn a_whole_number_past_the_largest_toml_takes_says_so() {
        let e = "numerics.trigger_seed=9223372036854775808"
            .parse::<Override>()
            .unwrap_err();
        assert!(e.detail.contains("2⁶³ − 1 = 9223372036854775807"), "{e}");
        assert!(
            "numerics.trigger_seed=9223372036854775807"
                .parse::<Override>()
                .is_ok()
        );
    }

    #[test]
    fn one_key_per_set() {
        // Everything after a line break used to be dropped without a word.
        let e = "tools.r=7.5\ntools.rp=3".parse::<Override>().unwrap_err();
        assert_eq!(e.origin, "--set tools.r=7.5\\ntools.rp=3");
        assert!(e.detail.contains("line break"), "{e}");
        // A second key hidden in the value is not a literal either.
        let e = "tools.r=7.5 rp=3".parse::<Override>().unwrap_err();
        assert!(e.detail.contains("expected a TOML literal"), "{e}");
    }
}
