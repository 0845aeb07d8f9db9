//! One rule for every file of every command: a command writes only into a folder that is new,
//! empty, or marked as wovenform's own (`.wovenform`); a folder that holds anything else is
//! refused before any work, naming one of its files, and nothing in it changes. A folder's
//! rows are never dropped by a resume: a frontier's folder resumed as a sweep, or along another
//! axis, keeps every row.

use std::path::Path;
use std::process::Output;

use crate::common::{preset, text, wovenform_in, write_file};

fn refused(o: &Output, words: &[&str]) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    for w in words {
        assert!(err.contains(w), "the message does not name `{w}`: {err}");
    }
}

fn ok(o: &Output) -> String {
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}\n{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    text(&o.stdout)
}

/// The names in a folder, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

const FABRIC: &str =
    "[fabric]\nundulation = false\nbending_rigidity = [0.08, 0.08]\nareal_mass = 300.0\n";

/// The paper's open box, r 4–20 mm (every 4 mm) for rp 15 and rm 10 mm: at standard it has a
/// boundary in range (about 5 mm), so the frontier runs between the grid's values; rm is
/// swept with one value so that the frontier can go along it too.
const EDGE: &str = "[sweep]\nr = [4.0, 8.0, 12.0, 16.0, 20.0]\nrp = [15.0]\nrm = [10.0]\n";

fn edge_file(d: &Path) -> String {
    let base = preset("paper-box-open.toml");
    write_file(
        d,
        "edge.toml",
        format!("base = {base:?}\n{EDGE}").as_bytes(),
    );
    "edge.toml".into()
}

#[test]
fn every_command_refuses_a_folder_that_holds_a_users_file_whatever_its_name() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    write_file(d, "glass.toml", FABRIC.as_bytes());
    let edge = edge_file(d);
    let open_box = preset("paper-box-open.toml");
    let quick = ["--accuracy", "coarse", "--set", "process.stroke=3"];
    let cases: Vec<(&str, Vec<&str>)> = vec![
        ("form.png", [&["run", &open_box][..], &quick].concat()),
        ("result.vtu", [&["run", &open_box][..], &quick].concat()),
        ("notes.txt", [&["run", &open_box][..], &quick].concat()),
        (
            "cantilever.png",
            vec!["cantilever", "glass.toml", "--length", "20"],
        ),
        ("results.json", vec!["sweep", &edge, "--accuracy", "coarse"]),
        ("report.png", vec!["sweep", &edge, "--accuracy", "coarse"]),
        ("frontier.csv", vec!["frontier", &edge, "--along", "r"]),
        ("sweep.lock", vec!["frontier", &edge, "--along", "r"]),
        ("figure6.png", vec!["law", "--curves"]),
        ("punch.stl", vec!["tools", &open_box]),
        (
            "converge.csv",
            vec!["converge", &open_box, "--sizes", "30,25,20"],
        ),
    ];
    for (k, (name, args)) in cases.iter().enumerate() {
        let folder = format!("mine{k}");
        std::fs::create_dir(d.join(&folder)).unwrap();
        std::fs::write(d.join(&folder).join(name), "the user's\n").unwrap();
        let o = wovenform_in(d, &[&args[..], &["--out", &folder]].concat());
        refused(&o, &[&format!("{folder}/{name}"), "did not write"]);
        assert_eq!(
            names(&d.join(&folder)),
            [*name],
            "{args:?}: nothing written"
        );
        let kept = std::fs::read_to_string(d.join(&folder).join(name)).unwrap();
        assert_eq!(kept, "the user's\n", "{args:?}");
    }
    // The issue's case to the letter: a frontier into a folder with the user's frontier.csv.
    let o = wovenform_in(d, &["frontier", &edge, "--along", "r", "--out", "mine6"]);
    assert_eq!(o.status.code(), Some(2));
    // An empty folder is taken, and marked; a second run replaces the first's files.
    std::fs::create_dir(d.join("empty")).unwrap();
    for _ in 0..2 {
        ok(&wovenform_in(
            d,
            &[&["run", &open_box][..], &quick, &["--out", "empty"]].concat(),
        ));
    }
    assert!(d.join("empty/.wovenform").is_file());
    assert!(d.join("empty/form.png").is_file());
}

#[test]
fn a_scene_named_as_an_output_in_a_folder_of_wovenforms_is_never_overwritten() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let open_box = preset("paper-box-open.toml");
    let quick = ["--accuracy", "coarse", "--set", "process.stroke=3"];
    ok(&wovenform_in(
        d,
        &[&["run", &open_box][..], &quick, &["--out", "r"]].concat(),
    ));
    // Each file a run may write, made the scene of a run into that same folder.
    let scene = std::fs::read(&open_box).unwrap();
    for name in [
        "wrinkles.png",
        "form.png",
        "newton_trace.csv",
        "summary.json",
    ] {
        std::fs::write(d.join("r").join(name), &scene).unwrap();
        let scene_path = format!("r/{name}");
        let o = wovenform_in(
            d,
            &[
                &["run", &scene_path][..],
                &quick,
                &["--newton-trace", "--out", "r"],
            ]
            .concat(),
        );
        refused(&o, &[&scene_path, "scene file"]);
        assert_eq!(std::fs::read(d.join("r").join(name)).unwrap(), scene);
    }
}

#[test]
fn a_frontiers_folder_resumed_as_a_sweep_or_along_another_axis_keeps_every_row() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let edge = edge_file(d);
    let rows = |d: &Path| {
        let text = std::fs::read_to_string(d.join("f/results.csv")).unwrap();
        let mut v: Vec<String> = text.lines().skip(1).map(String::from).collect();
        v.sort();
        v
    };
    let coarse = ["--accuracy", "standard"];
    let frontier = |along: &str, resume: bool| {
        let mut args = vec!["frontier", &edge, "--along", along, "--out", "f"];
        args.extend(coarse);
        if resume {
            args.push("--resume");
        }
        wovenform_in(d, &args)
    };
    ok(&frontier("r", false));
    let searched = rows(d);
    let csv = std::fs::read_to_string(d.join("f/frontier.csv")).unwrap();
    // Some of its runs lie between the grid's values of r (every 2 mm).
    let between = searched
        .iter()
        .filter(|l| {
            let r: f64 = l.split(',').next().unwrap().parse().unwrap();
            (r / 4.0).fract() != 0.0
        })
        .count();
    assert!(between > 0, "{searched:?}");
    // The grid resumed in the frontier's folder: nothing dropped, the grid's designs run.
    let said = text(
        &wovenform_in(
            d,
            &[&["sweep", &edge, "--out", "f", "--resume"][..], &coarse].concat(),
        )
        .stderr,
    );
    assert!(!said.contains("dropped"), "{said}");
    assert!(
        said.contains("of another grid left in results.csv"),
        "{said}"
    );
    let after = rows(d);
    // A design is its values (the id's hash): a run on the grid is renumbered, not lost.
    for design in searched.iter().map(|l| l.split(',').nth(15).unwrap()) {
        let values = design.split('-').nth(1).unwrap();
        assert!(
            after.iter().any(|l| l.contains(values)),
            "{design} dropped: {after:?}"
        );
    }
    // The frontier again: runs nothing, finds the same boundaries.
    let o = frontier("r", true);
    let out = ok(&o);
    assert!(out.contains("0 run now"), "{out}");
    assert_eq!(
        std::fs::read_to_string(d.join("f/frontier.csv")).unwrap(),
        csv
    );
    // Along the other axis (refused: one value of rm is no range) the folder is as it was.
    let before = rows(d);
    refused(
        &frontier("rm", true),
        &["--along rm", "two or more numbers"],
    );
    assert_eq!(rows(d), before);
    // Every field a row names is there.
    for line in rows(d) {
        let id = line.split(',').nth(15).unwrap().to_string();
        if line.contains("maps/") {
            assert!(d.join(format!("f/fields/{id}.json")).is_file(), "{id}");
        }
    }
}

/// A full disk (a 150 kB tmpfs, mounted where the machine lets this test: CI runs as root)
/// stops a frontier with an error naming the file: every run announced has its row and its
/// field, and the rows written are kept.
#[test]
fn a_full_disk_stops_a_frontier_naming_the_file_and_loses_no_announced_run() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let edge = edge_file(d);
    let full = d.join("full");
    if !crate::common::mount_small_tmpfs(&full, "150k") {
        return;
    }
    let o = wovenform_in(d, &["frontier", &edge, "--along", "r", "--out", "full/f"]);
    let rows = std::fs::read_to_string(full.join("f/results.csv")).unwrap_or_default();
    let fields: Vec<String> = std::fs::read_dir(full.join("f/fields"))
        .map(|e| {
            e.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    let _ = std::process::Command::new("umount").arg(&full).status();
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("full/f/") && err.contains("No space left") && err.contains("--resume"),
        "{err}"
    );
    // Each run announced ("[n] design VERDICT") is a row with its field.
    for line in err.lines().filter(|l| l.starts_with('[')) {
        let design = line.split_whitespace().nth(1).unwrap();
        assert!(rows.contains(design), "{design} announced, no row: {rows}");
        assert!(
            fields.contains(&format!("{design}.json")),
            "{design}: no field"
        );
    }
    assert!(rows.lines().count() >= 2, "{rows}");
}
