//! Values that would give a wrong answer without a word: two holders at once, nan and inf in a
//! swept axis, a whole-number key as a frontier's axis, rows judged without the wrinkle
//! figure their scene has; and the spellings a scene takes (a quoted dotted key) or refuses
//! with a message that says what it wants. Each is refused before any work, naming the file,
//! the key and what was expected, or answered right.

use crate::common;

use std::path::Path;
use std::process::Output;

use common::{preset, text, wovenform_in, write_file};

/// Asserts exit 2 with a message naming each of `words`, and that nothing was written.
fn refused(o: &Output, words: &[&str], dir: &Path) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    for w in words {
        assert!(err.contains(w), "the message does not name `{w}`: {err}");
    }
    assert!(!dir.join("o").exists(), "written before the refusal: {err}");
}

/// A sweep file over the open box with `rest` after its `base`.
fn sweep_file(dir: &Path, name: &str, rest: &str) -> String {
    let base = format!("base = {:?}\n{rest}", preset("paper-box-open.toml"));
    write_file(dir, name, base.as_bytes());
    name.to_string()
}

#[test]
fn a_pressure_swept_under_a_plates_force_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    // The plate's force would win: three pressures would give one answer.
    let f = sweep_file(
        d,
        "hp.toml",
        "[scene.process]\nholder_force = 2.0\n[sweep]\nholder_pressure = [0.1, 1.0, 10.0]\n",
    );
    for args in [
        vec!["sweep", &f, "--out", "o"],
        vec!["frontier", &f, "--along", "holder_pressure", "--out", "o"],
    ] {
        let o = wovenform_in(d, &args);
        refused(
            &o,
            &[
                "sweep.holder_pressure",
                "process.holder_force = 2 kN",
                "same answer",
            ],
            d,
        );
    }
    let f = sweep_file(
        d,
        "hf.toml",
        "[sweep]\nholder_pressure = [0.1, 1.0]\n\"process.holder_force\" = [1.0, 2.0]\n",
    );
    let o = wovenform_in(d, &["sweep", &f, "--out", "o"]);
    refused(
        &o,
        &[
            "sweep.holder_pressure",
            "process.holder_force",
            "same answer",
        ],
        d,
    );
    // A scene that sets both (a preset's pressure, a plate's force by --set) is pressed by the
    // plate, and says so: the pressure is no axis there, so nothing is silently unused.
    let box_file = preset("paper-box-open.toml");
    let o = wovenform_in(
        d,
        &[
            "run",
            &box_file,
            "--set",
            "process.holder_force=2.0",
            "--set",
            "process.stroke=3.0",
            "--set",
            "mesh.element_size=5.0",
            "--out",
            "run",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("holder plate pressed with 2 kN"),
        "{}",
        text(&o.stdout)
    );
}

#[test]
fn nan_and_inf_in_a_swept_axis_are_refused_by_name() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    for (name, values, shown) in [
        ("n.toml", "[nan, 10.0]", "NaN"),
        ("i.toml", "[4.0, inf]", "inf"),
        ("m.toml", "[4.0, -inf]", "-inf"),
    ] {
        let f = sweep_file(d, name, &format!("[sweep]\nr = {values}\n"));
        for args in [
            vec!["sweep", &f, "--out", "o"],
            vec!["frontier", &f, "--along", "r", "--out", "o"],
            vec!["slurm", &f, "--tasks", "2", "--out", "o"],
        ] {
            let o = wovenform_in(d, &args);
            refused(&o, &[name, &format!("sweep.r = {shown}"), "finite"], d);
        }
    }
}

#[test]
fn a_whole_number_key_is_no_frontier_axis_and_an_unknown_one_is_named_by_its_flag() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    let f = sweep_file(
        d,
        "ts.toml",
        "[sweep]\nr = [4.0, 10.0]\n\"numerics.trigger_seed\" = [1, 5]\n",
    );
    let o = wovenform_in(
        d,
        &[
            "frontier",
            &f,
            "--along",
            "numerics.trigger_seed",
            "--out",
            "o",
        ],
    );
    refused(&o, &["--along numerics.trigger_seed", "whole numbers"], d);
    let slurm = |key: &str| {
        wovenform_in(
            d,
            &["slurm", &f, "--frontier", key, "--tasks", "2", "--out", "o"],
        )
    };
    refused(
        &slurm("numerics.trigger_seed"),
        &["--frontier numerics.trigger_seed"],
        d,
    );
    let o = slurm("foo");
    refused(&o, &["--frontier foo", "r, numerics.trigger_seed"], d);
    assert!(!text(&o.stderr).contains("--along"), "{}", text(&o.stderr));
}

#[test]
fn rows_of_a_bending_scene_written_without_the_wrinkle_figure_are_run_again() {
    // A results.csv of a bending scene written before the wrinkle columns: its verdicts were
    // reached without wrinkles, so a resume runs them again rather than judge without them.
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    let f = sweep_file(
        d,
        "b.toml",
        "[scene.fabric]\nundulation = false\nbending_rigidity = [0.5, 0.5]\n\
         [scene.process]\nstroke = 6.0\n[scene.mesh]\nelement_size = 5.0\n[sweep]\nr = [8.0, 10.0]\n",
    );
    let o = wovenform_in(d, &["sweep", &f, "--out", "o"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let csv = d.join("o/results.csv");
    let full = std::fs::read_to_string(&csv).unwrap();
    let cut = full
        .lines()
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == "max_wrinkle_mm");
    let cut = cut.expect("a wrinkle column");
    let older: String = (full.lines())
        .map(|l| l.split(',').take(cut).collect::<Vec<_>>().join(",") + "\n")
        .collect();
    std::fs::write(&csv, older).unwrap();
    let o = wovenform_in(d, &["sweep", &f, "--out", "o", "--resume"]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("dropped 2 of a scene with bending"), "{err}");
    assert!(err.contains("2 designs to run"), "{err}");
    let again = std::fs::read_to_string(&csv).unwrap();
    assert!(
        again.lines().next().unwrap().contains("max_wrinkle_mm"),
        "{again}"
    );
    assert_eq!(again.lines().count(), 3, "{again}");
}

#[test]
fn a_quoted_dotted_key_is_a_key_in_a_scene_and_in_a_sweeps_scene_table() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    // As `[sweep]` spells its keys: the same stroke as `[process] stroke`.
    write_file(
        d,
        "s.toml",
        b"\"process.stroke\" = 4.0\n[mesh]\nelement_size = 5.0\n",
    );
    let o = wovenform_in(d, &["run", "s.toml", "--json", "--out", "r"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["stroke_mm"].as_f64(), Some(4.0));
    // Given both ways, it is refused, naming the key.
    write_file(
        d,
        "t.toml",
        b"\"process.stroke\" = 4.0\n[process]\nstroke = 3.0\n",
    );
    let o = wovenform_in(d, &["run", "t.toml", "--out", "o"]);
    refused(&o, &["t.toml", "\"process.stroke\" is given twice"], d);
    let f = sweep_file(
        d,
        "w.toml",
        "[scene]\n\"process.stroke\" = 4.0\n\"mesh.element_size\" = 5.0\n[sweep]\nr = [8.0]\n",
    );
    let o = wovenform_in(d, &["sweep", &f, "--out", "sw"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let json = std::fs::read_to_string(d.join("sw/results.json")).unwrap();
    assert!(json.contains("\"stroke\": 4.0"), "{json}");
}

#[test]
fn wrong_lengths_huge_seeds_and_huge_limits_are_said_in_a_line_a_person_reads() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    let box_file = preset("paper-box-open.toml");
    let run = |sets: &[&str]| {
        let mut args = vec!["run", box_file.as_str(), "--out", "o"];
        for s in sets {
            args.extend(["--set", s]);
        }
        wovenform_in(d, &args)
    };
    let o = run(&[
        "fabric.undulation=false",
        "fabric.bending_rigidity=[0.1,0.1,0.1]",
    ]);
    refused(&o, &["3 values: expected two numbers", "[B1, B2]"], d);
    let o = run(&["numerics.trigger_seed=9223372036854775808"]);
    refused(&o, &["9223372036854775807"], d);
    let o = run(&[
        "fabric.undulation=false",
        "fabric.bending_rigidity=[1e300,1e300]",
    ]);
    refused(&o, &["[1e300, 1e300]", "at most 1e5"], d);
    assert!(text(&o.stderr).len() < 400, "{}", text(&o.stderr));
    // A tiny wrinkle limit is printed as a number, not as 300 zeros.
    let o = wovenform_in(
        d,
        &[
            "run",
            &box_file,
            "--out",
            "w",
            "--accuracy",
            "coarse",
            "--set",
            "process.stroke=4.0",
            "--set",
            "fabric.undulation=false",
            "--set",
            "fabric.bending_rigidity=[0.5,0.5]",
            "--set",
            "fabric.wrinkle_limit_mm=1e-300",
        ],
    );
    let said = text(&o.stdout);
    assert!(said.contains("wrinkle limit 1e-300 mm"), "{said}");
    assert!(said.lines().all(|l| l.chars().count() < 300), "{said}");
}
