//! The tests of the house rules that the architecture page states: no file of the library uses a
//! module of a later layer, no two files use each other, no file is over 700 lines and no
//! function over 80. The first reads the sources as text:
//! each `crate::…`, `super::…` and `self::…` path outside comments and test modules, resolved
//! to the file that defines it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The layers, lowest first, as the architecture page numbers them (the guide holds no code).
const LAYERS: [&[&str]; 8] = [
    &["core"],
    &["show", "presets", "files", "machine", "stl"],
    &["scene"],
    &["accuracy", "verdict", "summary"],
    &["study"],
    &["report"],
    &["publish"],
    &["tui", "guide"],
];

/// The folders of `core`, lowest first, in the paper's order: a file of one uses only files of
/// its own folder or of those before it.
const CORE_LAYERS: [&str; 10] = [
    "vec3",
    "fabric",
    "membrane",
    "sparse",
    "solver",
    "tools",
    "contact",
    "wrinkles",
    "drawing",
    "specimens",
];

/// The layer of a top-level module.
fn layer(top: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&top))
}

/// A file's module path: `core/tools/surface.rs` → `[core, tools, surface]`, a `mod.rs` its
/// folder's, `lib.rs` the root.
fn module_of(file: &str) -> Vec<String> {
    let mut parts: Vec<String> = file
        .trim_end_matches(".rs")
        .split('/')
        .map(String::from)
        .collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    parts
}

/// The source as it builds the library: no comment lines, nothing from the first test module.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths a source uses, each as written after its `crate`, `super` or `self` (a group
/// `{a, b::c}` gives one path per item), with the module it is relative to.
fn used_paths(code: &str, me: &[String]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    for (at, _) in code.match_indices("::") {
        let head_start = code[..at].rfind(|c: char| !ident(c)).map_or(0, |i| i + 1);
        let head = &code[head_start..at];
        let before = code[..head_start].chars().last();
        if before.is_some_and(|c| c == ':' || ident(c)) {
            continue; // the middle of a longer path
        }
        let mut base: Vec<String> = match head {
            "crate" => Vec::new(),
            "self" => me.to_vec(),
            "super" => me[..me.len().saturating_sub(1)].to_vec(),
            _ => continue,
        };
        let mut rest = &code[at + 2..];
        while let Some(r) = rest.strip_prefix("super::") {
            base.pop();
            rest = r;
        }
        let items: Vec<&str> = if let Some(group) = rest.strip_prefix('{') {
            group.split('}').next().unwrap_or("").split(',').collect()
        } else {
            vec![rest]
        };
        for item in items {
            let path: Vec<String> = item
                .trim()
                .split("::")
                .map(|p| p.chars().take_while(|&c| ident(c)).collect::<String>())
                .take_while(|p| !p.is_empty())
                .collect();
            out.push([base.clone(), path].concat());
        }
    }
    out
}

/// Every library file under `src/` (not the binary's `main.rs` and `cli/`) with its code.
fn library(src: &Path) -> BTreeMap<String, String> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let rel = path
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            if path.is_dir() && rel != "cli" {
                walk(root, &path, out);
            } else if rel.ends_with(".rs") && rel != "main.rs" {
                out.insert(rel, code(&std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(src, src, &mut out);
    out
}

/// Which file each file uses (the file defining the longest prefix of each path it uses).
fn uses(files: &BTreeMap<String, String>) -> BTreeSet<(String, String)> {
    let by_module: BTreeMap<Vec<String>, &String> =
        files.keys().map(|f| (module_of(f), f)).collect();
    let mut edges = BTreeSet::new();
    for (file, code) in files {
        for path in used_paths(code, &module_of(file)) {
            let target = (1..=path.len())
                .rev()
                .find_map(|k| by_module.get(&path[..k]).copied());
            if let Some(target) = target.filter(|t| *t != file) {
                edges.insert((file.clone(), target.clone()));
            }
        }
    }
    edges
}

#[test]
fn no_file_uses_a_later_layer_and_no_two_files_use_each_other() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let files = library(&src);
    let edges = uses(&files);
    let top = |f: &str| module_of(f).first().cloned().unwrap_or_default();
    let mut wrong = Vec::new();
    for (a, b) in &edges {
        let (ta, tb) = (top(a), top(b));
        if ta.is_empty() || tb.is_empty() || ta == tb {
            continue;
        }
        match (layer(&ta), layer(&tb)) {
            (Some(la), Some(lb)) if la < lb => wrong.push(format!("{a} uses {b}, a later layer")),
            (None, _) | (_, None) => wrong.push(format!("{a} → {b}: a module of no layer")),
            _ => {}
        }
    }
    // Inside core, the folders in the paper's order.
    let core_layer = |f: &str| {
        let m = module_of(f);
        (m.first().map(String::as_str) == Some("core") && m.len() > 1)
            .then(|| CORE_LAYERS.iter().position(|l| *l == m[1]))
            .flatten()
    };
    for (a, b) in &edges {
        if let (Some(la), Some(lb)) = (core_layer(a), core_layer(b))
            && la < lb
        {
            wrong.push(format!("{a} uses {b}, a later folder of core"));
        }
        let in_core = |f: &str| module_of(f).first().map(String::as_str) == Some("core");
        if in_core(a) && in_core(b) && module_of(a).len() > 1 && core_layer(a).is_none() {
            wrong.push(format!(
                "{a}: a folder of core that CORE_LAYERS does not name"
            ));
        }
    }
    for (a, b) in &edges {
        // A folder's mod.rs and its own files share names both ways (re-exports).
        let parent =
            |x: &str, y: &str| x.ends_with("mod.rs") && module_of(y).starts_with(&module_of(x));
        if a < b && edges.contains(&(b.clone(), a.clone())) && !parent(a, b) && !parent(b, a) {
            wrong.push(format!("{a} and {b} use each other"));
        }
    }
    assert!(
        wrong.is_empty(),
        "the layering of src/guide/architecture.md is broken:\n{}",
        wrong.join("\n")
    );
    // The test sees the uses it must: a known one.
    assert!(
        edges.contains(&("scene/mod.rs".into(), "core/drawing/mod.rs".into())),
        "{edges:?}"
    );
    assert!(
        edges.contains(&(
            "core/membrane/element.rs".into(),
            "core/fabric/law.rs".into()
        )),
        "{edges:?}"
    );
}

/// The functions of a source longer than `most` lines (from `fn` to its closing brace at the
/// same indentation), each as `name (lines)`.
fn long_functions(text: &str, most: usize) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut long = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let body = line.trim_start();
        let indent = &line[..line.len() - body.len()];
        let head = ["pub fn ", "pub(crate) fn ", "pub(super) fn ", "fn "]
            .iter()
            .find_map(|p| body.strip_prefix(p));
        let Some(name) = head.map(|h| h.split(['(', '<']).next().unwrap_or("")) else {
            continue;
        };
        if body.ends_with(';') || (body.ends_with('}') && body.contains('{')) {
            continue; // a declaration, or a one-line function
        }
        let close = format!("{indent}}}");
        let end = (i..lines.len()).find(|&j| lines[j] == close);
        if let Some(end) = end.filter(|&end| end - i + 1 > most) {
            long.push(format!("{name} ({} lines)", end - i + 1));
        }
    }
    long
}

#[test]
fn no_file_over_700_lines_and_no_function_over_80() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut wrong = Vec::new();
    let mut stack = vec![src.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let name = path.strip_prefix(&src).unwrap().display().to_string();
            let lines = text.lines().count();
            if lines > 700 {
                wrong.push(format!("{name}: {lines} lines"));
            }
            for f in long_functions(&text, 80) {
                wrong.push(format!("{name}: fn {f}"));
            }
        }
    }
    wrong.sort();
    assert!(
        wrong.is_empty(),
        "over the house's sizes:\n{}",
        wrong.join("\n")
    );
    // The scan sees a long function when there is one.
    let body = "    let x = 1;\n".repeat(81);
    let long = format!("fn long() {{\n{body}}}\n");
    assert_eq!(long_functions(&long, 80), ["long (83 lines)"]);
}

/// The command line's files (`cli/*.rs`) with their code.
fn command_line(src: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(src.join("cli")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "rs") {
            let name = format!("cli/{}", path.file_name().unwrap().to_string_lossy());
            out.insert(name, code(&std::fs::read_to_string(&path).unwrap()));
        }
    }
    out
}

#[test]
fn the_command_line_is_thin_and_its_files_do_not_use_each_other() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let files = command_line(&src);
    let mut wrong = Vec::new();
    // Each command's `exec` reads on one screen: parse, call the library, print.
    for (name, code) in &files {
        for f in long_functions(code, 40) {
            if f.starts_with("exec ") {
                wrong.push(format!("{name}: fn {f}, over 40"));
            }
        }
    }
    // `super::x` from one command file to another, both ways, is a circle.
    let uses = |a: &str, b: &str| {
        let stem = b.trim_start_matches("cli/").trim_end_matches(".rs");
        files[a].contains(&format!("super::{stem}::"))
            || files[a].contains(&format!("super::{stem};"))
    };
    for a in files.keys() {
        for b in files.keys() {
            if a < b && !a.ends_with("mod.rs") && !b.ends_with("mod.rs") && uses(a, b) && uses(b, a)
            {
                wrong.push(format!("{a} and {b} use each other"));
            }
        }
    }
    assert!(wrong.is_empty(), "the command line:\n{}", wrong.join("\n"));
    assert!(files.contains_key("cli/run.rs"), "{:?}", files.keys());
}
