//! `wovenform frontier` end to end with the real binary: its outputs (the table, the CSV, the
//! JSON, the chart and each run as a row of results.csv), its refusals, a resume that runs
//! nothing again, and shards, merge and the Slurm scripts giving the frontier of one run.
//! The paper's open box at the coarse level for rp 15 mm and rm 7.5 and 10 mm, r 4–20 mm
//! (a run takes about 0.1 s; both pairs have a boundary in range).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common;
use common::{text, wovenform_in as wovenform};

fn frontier_file(dir: &Path, sweep: &str) -> PathBuf {
    let base = common::preset("paper-box-open.toml");
    let path = dir.join("edge.toml");
    std::fs::write(&path, format!("base = {base:?}\n[sweep]\n{sweep}")).unwrap();
    path
}

const SWEEP: &str = "r = { start = 4.0, stop = 20.0, count = 9 }\nrp = [15.0]\nrm = [7.5, 10.0]\nfriction = [0.2]\n";

fn ok(o: Output) -> String {
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}\n{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    text(&o.stdout)
}

fn frontier(dir: &Path, out: &str, extra: &[&str]) -> Output {
    let file = frontier_file(dir, SWEEP);
    let args = [
        &[
            "frontier",
            file.to_str().unwrap(),
            "--along",
            "r",
            "--out",
            out,
        ][..],
        &["--accuracy", "coarse"],
        extra,
    ]
    .concat();
    wovenform(dir, &args)
}

/// The CSV's records without the runs column (shards count their own), sorted.
fn boundaries(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines.sort();
    lines
}

#[test]
fn the_frontier_writes_its_table_files_and_rows_and_a_resume_runs_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let stdout = ok(frontier(dir, "f", &[]));
    for words in [
        "The frontier along r",
        "feasible where r ≥",
        "runs against 18",
    ] {
        assert!(stdout.contains(words), "{words}: {stdout}");
    }
    let csv = std::fs::read_to_string(dir.join("f/frontier.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert_eq!(
        header,
        "rm,along,boundary_mm,low_mm,high_mm,search_low_mm,search_high_mm,governing,feasible,runs,note"
    );
    assert_eq!(csv.lines().count(), 3, "{csv}");
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let [b, lo, hi]: [f64; 3] = [2, 3, 4].map(|i| f[i].parse().unwrap());
        assert!(lo <= b && b <= hi && (4.0..=20.0).contains(&b), "{line}");
        assert_eq!((f[7], f[8]), ("shear", "above"), "{line}");
    }
    let png = std::fs::read(dir.join("f/frontier.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("f/frontier.json")).unwrap())
            .unwrap();
    let runs = json["runs"].as_u64().unwrap() as usize;
    assert_eq!(json["grid_runs"], 18);
    let rows = std::fs::read_to_string(dir.join("f/results.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + runs, "a row per run");
    // Without --resume the folder is refused; with it nothing runs again.
    let refused = frontier(dir, "f", &[]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        text(&refused.stderr).contains("--resume"),
        "{}",
        text(&refused.stderr)
    );
    let again = ok(frontier(dir, "f", &["--resume", "--json"]));
    let again: serde_json::Value = serde_json::from_str(&again).unwrap();
    assert_eq!(again["ran_now"], 0);
    assert_eq!(again["lines"], json["lines"]);
}

#[test]
fn an_axis_that_cannot_be_searched_is_refused_with_the_file_and_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let file = frontier_file(tmp.path(), SWEEP);
    for (along, words) in [
        ("friction", "expected two or more numbers"),
        (
            "clearance",
            "not a swept key; expected one of the [sweep] table's: r, rp, rm, friction",
        ),
    ] {
        let o = wovenform(
            tmp.path(),
            &[
                "frontier",
                file.to_str().unwrap(),
                "--along",
                along,
                "--out",
                "x",
            ],
        );
        assert_eq!(o.status.code(), Some(2), "{along}");
        let e = text(&o.stderr);
        assert!(e.contains(words) && e.contains("edge.toml"), "{along}: {e}");
        assert!(
            !tmp.path().join("x").exists(),
            "nothing written before the check"
        );
    }
}

#[test]
fn values_that_break_a_bound_shorten_the_range_and_are_named() {
    // r = 40 mm does not fit the 60 mm punch: the search says so instead of answering there.
    let tmp = tempfile::tempdir().unwrap();
    let file = frontier_file(tmp.path(), "r = [10.0, 40.0]\nrp = [15.0]\n");
    let o = wovenform(
        tmp.path(),
        &[
            "frontier",
            file.to_str().unwrap(),
            "--along",
            "r",
            "--out",
            "f",
            "--accuracy",
            "coarse",
        ],
    );
    let out = ok(o);
    assert!(out.contains("no answer at r 40 mm: tools.r = 40"), "{out}");
}

#[test]
fn shards_merged_and_the_slurm_scripts_give_the_frontier_of_one_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(frontier(dir, "whole", &[]));
    ok(frontier(dir, "s1", &["--shard", "1/2"]));
    ok(frontier(dir, "s2", &["--shard", "2/2"]));
    ok(wovenform(dir, &["merge", "s1", "s2", "--out", "merged"]));
    ok(frontier(dir, "merged", &["--resume"]));
    assert_eq!(
        boundaries(&dir.join("merged/frontier.csv")),
        boundaries(&dir.join("whole/frontier.csv"))
    );
    // The Slurm array: a task per shard of the combinations, the merge writes the frontier.
    let file = frontier_file(dir, SWEEP);
    ok(wovenform(
        dir,
        &[
            "slurm",
            file.to_str().unwrap(),
            "--frontier",
            "r",
            "--out",
            "cluster",
            "--tasks",
            "5",
            "--min-task-s",
            "0",
            "--accuracy",
            "coarse",
        ],
    ));
    let scripts = dir.join("cluster/slurm");
    let array = std::fs::read_to_string(scripts.join("array.sh")).unwrap();
    assert!(
        array.contains("#SBATCH --array=1-2"),
        "two combinations, two tasks: {array}"
    );
    assert!(
        array.contains(" frontier ") && array.contains("--along=r"),
        "{array}"
    );
    for i in ["1", "2"] {
        let st = Command::new("bash")
            .arg(scripts.join("array.sh"))
            .env("SLURM_ARRAY_TASK_ID", i)
            .env("SLURM_CPUS_PER_TASK", "1")
            .current_dir(dir)
            .output()
            .unwrap();
        assert!(st.status.success(), "{}", text(&st.stderr));
    }
    let st = Command::new("bash")
        .arg(scripts.join("merge.sh"))
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(st.status.success(), "{}", text(&st.stderr));
    assert_eq!(
        boundaries(&dir.join("cluster/frontier.csv")),
        boundaries(&dir.join("whole/frontier.csv"))
    );
}
