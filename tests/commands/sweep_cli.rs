//! `wovenform sweep` and `wovenform merge` end to end, with the real binary on small grids: the
//! open box on a 140 mm blank, 5 mm elements and 4 mm of stroke (a design takes ~0.1 s).
//!
//! The grid used by most tests, r × friction (friction 1.5 breaks a bound: invalid, not run):
//!
//! ```text
//!              friction 0.1   friction 0.2   friction 1.5
//!   r = 5 mm      d000           d001        d002 INVALID
//!   r = 10 mm     d003           d004        d005 INVALID
//! ```

use std::collections::{BTreeMap, HashSet};
use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::Value;

use crate::common;
use common::{text, wovenform_in as wovenform};

fn preset(name: &str) -> PathBuf {
    PathBuf::from(common::preset(name))
}

/// The quick scene: what the sweep file's [scene] puts over the open box, as `--set`s for `run`.
const QUICK: [&str; 3] = [
    "mesh.element_size=5.0",
    "process.stroke=4.0",
    "blank.size=140.0",
];

/// Writes a sweep file over the open-box preset with the quick scene and `sweep` as its
/// [sweep] table.
fn sweep_file(dir: &Path, name: &str, sweep: &str) -> PathBuf {
    let base = preset("paper-box-open.toml");
    let text = format!(
        "base = {:?}\n\n[scene]\nmesh.element_size = 5.0\nprocess.stroke = 4.0\nblank.size = 140.0\n\n[sweep]\n{sweep}",
        base.to_str().unwrap()
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const GRID: &str = "r = [5.0, 10.0]\nfriction = [0.1, 0.2, 1.5]\n";

/// Runs `sweep` and checks it succeeded.
fn sweep(dir: &Path, file: &Path, out: &str, extra: &[&str]) -> Output {
    let args = [&["sweep", file.to_str().unwrap(), "--out", out][..], extra].concat();
    let o = wovenform(dir, &args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}\nstdout: {}\nstderr: {}",
        text(&o.stdout),
        text(&o.stderr)
    );
    o
}

/// The rows of a results.csv, each a map column → value, and the header (read with the csv
/// crate, which knows RFC 4180 quoting).
fn read_csv(path: &Path) -> (Vec<String>, Vec<BTreeMap<String, String>>) {
    let s = std::fs::read_to_string(path).unwrap();
    assert!(s.ends_with('\n'), "the last row is complete");
    let mut reader = csv::Reader::from_reader(s.as_bytes());
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    let rows = reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            assert_eq!(r.len(), header.len(), "{r:?}");
            header
                .iter()
                .cloned()
                .zip(r.iter().map(String::from))
                .collect()
        })
        .collect();
    (header, rows)
}

/// Rows by design id, without the columns that change from run to run.
fn comparable(rows: &[BTreeMap<String, String>]) -> BTreeMap<String, BTreeMap<String, String>> {
    rows.iter()
        .map(|r| {
            let mut r = r.clone();
            r.remove("wall_s");
            (r["design"].clone(), r)
        })
        .collect()
}

#[test]
fn rows_equal_run_one_row_per_design_and_invalid_designs_are_listed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = sweep_file(dir, "grid.toml", GRID);
    let o = sweep(dir, &file, "out", &["--jobs", "2"]);
    let out = dir.join("out");
    let (header, rows) = read_csv(&out.join("results.csv"));
    assert_eq!(
        header.join(","),
        "r,rp,rm,friction,holder_pressure,max_shear_deg,max_tension_n,punch_force_n,max_shear_err_deg,max_tension_err_pct,punch_force_err_pct,feasible,converged,wall_s,map,design,verdict,failure,max_wrinkle_mm,max_wrinkle_err_mm,steps,newton_iterations"
    );
    assert_eq!(rows.len(), 6, "one row per design");
    let ids: HashSet<&str> = rows.iter().map(|r| r["design"].as_str()).collect();
    assert_eq!(ids.len(), 6);
    for r in &rows {
        if r["friction"] == "1.5" {
            assert_eq!(r["verdict"], "INVALID", "{r:?}");
            assert_eq!(r["converged"], "false");
            assert_eq!(r["feasible"], "false");
            assert_eq!(r["max_shear_deg"], "");
            assert_eq!(r["map"], "");
            assert_eq!(
                (r["steps"].as_str(), r["newton_iterations"].as_str()),
                ("", "")
            );
            assert!(r["failure"].contains("process.friction = 1.5"), "{r:?}");
        } else {
            assert_eq!(r["converged"], "true", "{r:?}");
            assert!(out.join(&r["map"]).is_file(), "{}", r["map"]);
            assert_eq!(r["rp"], "15");
            assert_eq!(r["holder_pressure"], "1");
        }
    }
    // Two designs run by `run --json`: the same figures to the printed precision.
    for (r, friction) in [("5", "0.1"), ("10", "0.2")] {
        let row = rows
            .iter()
            .find(|x| x["r"] == r && x["friction"] == friction)
            .unwrap();
        let tools_r = format!("tools.r={r}");
        let fr = format!("process.friction={friction}");
        let base = preset("paper-box-open.toml");
        let mut args = vec!["run", base.to_str().unwrap(), "--json", "--out", "single"];
        for s in QUICK.iter().chain([&tools_r.as_str(), &fr.as_str()]) {
            args.extend(["--set", s]);
        }
        let run = wovenform(dir, &args);
        assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
        let json: Value = serde_json::from_str(text(&run.stdout).trim()).unwrap();
        for (column, decimals) in [
            ("max_shear_deg", 4),
            ("max_tension_n", 3),
            ("punch_force_n", 3),
        ] {
            let printed: f64 = row[column].parse().unwrap();
            let exact = json[column].as_f64().unwrap();
            let half = 0.5 * 10f64.powi(-decimals) * (1.0 + 1e-9);
            assert!(
                (printed - exact).abs() <= half,
                "{column}: sweep {printed} against run {exact}"
            );
            assert_eq!(
                row[column].split('.').nth(1).map(str::len),
                Some(decimals as usize)
            );
        }
        assert_eq!(row["feasible"], json["feasible"].to_string());
        assert_eq!(row["converged"], json["converged"].to_string());
        // What the run cost: the same load steps and Newton iterations as the single run.
        assert_eq!(row["steps"], json["steps"].to_string());
        assert_eq!(
            row["newton_iterations"],
            json["newton_iterations"].to_string()
        );
    }
    // results.json: the version, the base scene as run, the grid, every row.
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(json["base_scene"]["mesh"]["element_size"], 5.0);
    assert_eq!(json["base_scene"]["fabric"]["undulation"], false);
    assert_eq!(json["rows"].as_array().unwrap().len(), 6);
    assert_eq!(json["designs"], 6);
    assert_eq!(json["sweep"][0]["column"], "r");
    // The pictures.
    let report = image::open(out.join("report.png")).unwrap();
    assert!(report.width() > 1500 && report.height() > 900);
    let map = image::open(out.join(&rows[2]["map"])).unwrap();
    assert_eq!((map.width(), map.height()), (1100, 900));
    // The table: sorted feasible first, marked, with units.
    let stdout = text(&o.stdout);
    let first_invalid = stdout.find("INVALID").unwrap();
    let last_feasible = stdout
        .rfind("FEASIBLE ")
        .unwrap_or(0)
        .max(stdout.rfind("✓").unwrap());
    assert!(last_feasible < first_invalid, "{stdout}");
    assert!(
        stdout.contains("max shear") && stdout.contains('°'),
        "{stdout}"
    );
    assert!(
        stdout.contains("4 feasible, 0 marginal, 0 infeasible, 0 failed, 2 invalid"),
        "{stdout}"
    );
}

#[test]
fn resume_after_a_kill_recomputes_only_what_is_missing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = sweep_file(dir, "grid.toml", GRID);
    sweep(dir, &file, "out", &[]);
    let csv = dir.join("out/results.csv");
    let full = std::fs::read_to_string(&csv).unwrap();
    let (_, all) = read_csv(&csv);
    // Killed while writing the fifth line: the header, three rows, half of the fourth.
    let lines: Vec<&str> = full.split_inclusive('\n').collect();
    let kept: Vec<&str> = lines[1..4].to_vec();
    let half = &lines[4][..lines[4].len() / 2];
    std::fs::write(&csv, format!("{}{}{half}", lines[0], kept.concat())).unwrap();

    let o = sweep(dir, &file, "out", &["--resume"]);
    let err = text(&o.stderr);
    assert!(
        err.contains("kept 3 rows, dropped 1 half-written last line; 3 designs to run"),
        "{err}"
    );
    let after = std::fs::read_to_string(&csv).unwrap();
    for line in &kept {
        assert!(after.contains(line), "a kept row changed: {line}");
    }
    let (_, rows) = read_csv(&csv);
    assert_eq!(rows.len(), 6, "no missing row, no duplicate");
    assert_eq!(comparable(&rows), comparable(&all));

    // Nothing left to do: a second resume runs nothing and keeps every row.
    let o = sweep(dir, &file, "out", &["--resume"]);
    assert!(
        text(&o.stderr).contains("kept 6 rows; 0 designs to run"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(std::fs::read_to_string(&csv).unwrap().lines().count(), 7);

    // Another base scene: refused, and the folder is left as it was.
    let o = wovenform(
        dir,
        &[
            "sweep",
            file.to_str().unwrap(),
            "--out",
            "out",
            "--resume",
            "--set",
            "process.stroke=3.0",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("another base scene"),
        "{}",
        text(&o.stderr)
    );
    // Without --resume an existing results.csv is not overwritten.
    let o = wovenform(dir, &["sweep", file.to_str().unwrap(), "--out", "out"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("--resume"), "{}", text(&o.stderr));
    assert_eq!(read_csv(&csv).1.len(), 6);
}

#[test]
fn three_shards_merge_to_the_whole_sweep() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = sweep_file(dir, "grid.toml", GRID);
    sweep(dir, &file, "whole", &[]);
    let mut seen = HashSet::new();
    for i in 1..=3 {
        let shard = format!("{i}/3");
        sweep(
            dir,
            &file,
            &format!("shard{i}"),
            &["--shard", &shard, "--jobs", "1"],
        );
        let (_, rows) = read_csv(&dir.join(format!("shard{i}/results.csv")));
        assert_eq!(rows.len(), 2, "shard {shard}");
        for r in rows {
            let index: usize = r["design"][1..4].parse().unwrap();
            assert_eq!(index % 3, i - 1, "design index modulo 3");
            assert!(seen.insert(r["design"].clone()), "disjoint shards");
        }
    }
    let o = wovenform(
        dir,
        &["merge", "shard1", "shard2", "shard3", "--out", "merged"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let (h1, whole) = read_csv(&dir.join("whole/results.csv"));
    let (h2, merged) = read_csv(&dir.join("merged/results.csv"));
    assert_eq!(h1, h2);
    assert_eq!(comparable(&merged), comparable(&whole));
    assert!(dir.join("merged/report.png").is_file());
    for r in merged.iter().filter(|r| !r["map"].is_empty()) {
        assert!(dir.join("merged").join(&r["map"]).is_file());
    }
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("merged/results.json")).unwrap())
            .unwrap();
    assert_eq!(json["rows"].as_array().unwrap().len(), 6);

    // Merging again into a folder of this sweep keeps its rows (a merge can be run again),
    // whether or not that folder is among the inputs.
    let o = wovenform(dir, &["merge", "shard1", "--out", "merged"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(
        comparable(&read_csv(&dir.join("merged/results.csv")).1),
        comparable(&whole)
    );
    let o = wovenform(dir, &["merge", "merged", "shard2", "--out", "merged"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(
        comparable(&read_csv(&dir.join("merged/results.csv")).1),
        comparable(&whole)
    );

    // A folder of another sweep is refused.
    let lock = dir.join("shard3/sweep.lock");
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&lock).unwrap()).unwrap();
    v["base_hash"] = Value::String("0000000000000000".into());
    std::fs::write(&lock, v.to_string()).unwrap();
    let o = wovenform(dir, &["merge", "shard1", "shard3", "--out", "bad"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("different sweeps"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn a_failing_design_yields_its_row_and_the_others_go_on() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // No holder pressure: nothing holds the blank, the model has no unique answer.
    let file = sweep_file(
        dir,
        "failing.toml",
        "r = 5.0\nholder_pressure = [1.0, 0.0]\nfriction = [0.2, 1.5]\n",
    );
    let o = sweep(dir, &file, "out", &[]);
    let (header, rows) = read_csv(&dir.join("out/results.csv"));
    assert!(header.contains(&"holder_pressure".to_string()));
    assert_eq!(rows.len(), 4);
    let find = |p: &str, f: &str| {
        rows.iter()
            .find(|r| r["holder_pressure"] == p && r["friction"] == f)
            .unwrap()
    };
    let failed = find("0", "0.2");
    assert_eq!(failed["verdict"], "FAILED", "{failed:?}");
    assert_eq!(failed["converged"], "false");
    assert!(failed["failure"].contains("no unique shape"), "{failed:?}");
    let ok = find("1", "0.2");
    assert_eq!(ok["verdict"], "FEASIBLE", "{ok:?}");
    assert_eq!(ok["converged"], "true");
    assert_eq!(find("1", "1.5")["verdict"], "INVALID");
    assert!(text(&o.stdout).contains("1 feasible, 0 marginal, 0 infeasible, 1 failed, 2 invalid"));
}

#[test]
fn bad_input_is_refused_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = sweep_file(dir, "grid.toml", GRID);
    let f = file.to_str().unwrap();
    let o = wovenform(dir, &["sweep", f, "--out", "/proc/forbidden"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("/proc/forbidden"),
        "{}",
        text(&o.stderr)
    );
    let unknown = sweep_file(dir, "unknown.toml", "r = [5.0]\nfrction = [0.1]\n");
    let o = wovenform(dir, &["sweep", unknown.to_str().unwrap(), "--out", "x"]);
    assert_eq!(o.status.code(), Some(2));
    let err = text(&o.stderr);
    assert!(
        err.contains("unknown.toml") && err.contains("sweep.frction"),
        "{err}"
    );
    for bad in [["--shard", "4/3"], ["--jobs", "0"], ["--set", "tools.r=-1"]] {
        let o = wovenform(dir, &[&["sweep", f, "--out", "y"][..], &bad[..]].concat());
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {}", text(&o.stderr));
    }
    assert!(!dir.join("x").exists() && !dir.join("y").exists());
}

#[test]
fn absurd_sizes_are_invalid_rows_kept_on_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // A 1 km blank or 0.001 mm elements: billions of elements, refused before any mesh.
    let file = sweep_file(
        dir,
        "sizes.toml",
        "\"blank.size\" = [140.0, 1e6]\n\"mesh.element_size\" = [5.0, 0.001]\n",
    );
    for jobs in ["1", "2"] {
        let out = format!("out-{jobs}");
        let o = sweep(dir, &file, &out, &["--jobs", jobs]);
        let (_, rows) = read_csv(&dir.join(&out).join("results.csv"));
        assert_eq!(rows.len(), 4, "{}", text(&o.stderr));
        let run: Vec<_> = rows.iter().filter(|r| r["verdict"] != "INVALID").collect();
        assert_eq!(run.len(), 1, "{rows:?}");
        assert_eq!(run[0]["blank.size"], "140");
        for r in rows.iter().filter(|r| r["verdict"] == "INVALID") {
            assert!(
                r["failure"].starts_with("mesh.element_size = ") && r["failure"].contains("memory"),
                "{r:?}"
            );
        }
        assert!(text(&o.stdout).contains("3 invalid"), "{}", text(&o.stdout));
        let o = sweep(dir, &file, &out, &["--resume"]);
        assert!(
            text(&o.stderr).contains("kept 4 rows; 0 designs to run"),
            "{}",
            text(&o.stderr)
        );
    }
}

/// Writes rows (maps column → value) back as a results.csv with `header`.
fn write_csv(path: &Path, header: &[String], rows: &[BTreeMap<String, String>]) {
    let mut w = csv::Writer::from_path(path).unwrap();
    w.write_record(header).unwrap();
    for r in rows {
        let names = header.iter().map(|h| r.get(h).map_or("", String::as_str));
        w.write_record(names).unwrap();
    }
    w.flush().unwrap();
}

/// A `results.csv` written before the later columns (the wrinkle columns, then the run's load
/// steps and Newton iterations: the same columns without them) is this sweep's: its rows are
/// kept on `--resume`, and the file is written again with those columns, empty for the kept
/// rows (what they were is not known).
#[test]
fn a_results_file_from_before_the_later_columns_resumes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = sweep_file(dir, "grid.toml", GRID);
    sweep(dir, &file, "out", &[]);
    let csv = dir.join("out/results.csv");
    let (header, all) = read_csv(&csv);
    for lacking in [
        &["steps", "newton_iterations"][..],
        &[
            "max_wrinkle_mm",
            "max_wrinkle_err_mm",
            "steps",
            "newton_iterations",
        ][..],
    ] {
        let older: Vec<String> = header
            .iter()
            .filter(|h| !lacking.contains(&h.as_str()))
            .cloned()
            .collect();
        assert_eq!(older.len() + lacking.len(), header.len());
        write_csv(&csv, &older, &all);
        let o = sweep(dir, &file, "out", &["--resume"]);
        let err = text(&o.stderr);
        assert!(err.contains("kept 6 rows"), "{lacking:?}: {err}");
        let (again, rows) = read_csv(&csv);
        assert_eq!(again, header);
        let known = |rows: &[BTreeMap<String, String>]| {
            let mut c = comparable(rows);
            for r in c.values_mut() {
                r.retain(|k, _| !lacking.contains(&k.as_str()));
            }
            c
        };
        assert_eq!(known(&rows), known(&all), "{lacking:?}");
        assert!(
            rows.iter()
                .all(|r| r["steps"].is_empty() && r["newton_iterations"].is_empty()),
            "{lacking:?}: counts not known are written empty"
        );
    }
}

#[test]
fn rows_edited_by_hand_are_run_again_and_an_edited_header_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = sweep_file(dir, "grid.toml", GRID);
    sweep(dir, &file, "out", &[]);
    let csv = dir.join("out/results.csv");
    let (header, all) = read_csv(&csv);
    let mut edited = all.clone();
    let ran: Vec<usize> = (0..edited.len())
        .filter(|&i| !edited[i]["map"].is_empty())
        .collect();
    let shear: f64 = edited[ran[0]]["max_shear_deg"].parse().unwrap();
    edited[ran[0]].insert("max_shear_deg".into(), format!("{:.4}", shear - 10.0));
    let verdict = if edited[ran[1]]["verdict"] == "FEASIBLE" {
        "INFEASIBLE"
    } else {
        "FEASIBLE"
    };
    edited[ran[1]].insert("verdict".into(), verdict.into());
    write_csv(&csv, &header, &edited);
    let o = sweep(dir, &file, "out", &["--resume"]);
    let err = text(&o.stderr);
    assert!(
        err.contains("kept 4 rows, dropped 2 that disagree with their field file"),
        "{err}"
    );
    assert!(err.contains("2 designs to run"), "{err}");
    assert_eq!(comparable(&read_csv(&csv).1), comparable(&all));
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/results.json")).unwrap())
            .unwrap();
    let shears: Vec<f64> = json["rows"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|r| r["max_shear_deg"].as_f64())
        .collect();
    assert!(
        shears.iter().all(|s| (s - (shear - 10.0)).abs() > 1e-3),
        "{shears:?}"
    );

    // A renamed column: refused (exit 2), naming the file, the column and the expected ones,
    // and the rows are left as they were.
    let mut renamed = header.clone();
    renamed[header.iter().position(|h| h == "max_shear_deg").unwrap()] = "maxshear".into();
    let rows = read_csv(&csv).1;
    let rows: Vec<_> = rows
        .into_iter()
        .map(|mut r| {
            let v = r.remove("max_shear_deg").unwrap();
            r.insert("maxshear".into(), v);
            r
        })
        .collect();
    write_csv(&csv, &renamed, &rows);
    let before = std::fs::read_to_string(&csv).unwrap();
    let f = file.to_str().unwrap();
    let o = wovenform(dir, &["sweep", f, "--out", "out", "--resume"]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("out/results.csv")
            && err.contains("`maxshear`")
            && err.contains(&header.join(",")),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), before);
}

#[test]
fn a_folder_in_use_is_refused_and_a_stale_lock_taken_over() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = sweep_file(dir, "one.toml", "r = 10.0\n");
    let f = file.to_str().unwrap();
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    // A folder a sweep made (its mark), whose lock file is there.
    std::fs::write(out.join(wovenform::files::FOLDER_MARKER), "").unwrap();
    let lock_path = out.join("sweep.pid");
    // Another sweep holds the folder (this test's process, its pid in the file, locked).
    let held = std::fs::File::create(&lock_path).unwrap();
    std::fs::write(&lock_path, format!("{}\n", std::process::id())).unwrap();
    held.try_lock().unwrap();
    let o = wovenform(dir, &["sweep", f, "--out", "out", "--resume"]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("out: another sweep is writing into this folder")
            && err.contains(&format!("pid {}", std::process::id())),
        "{err}"
    );
    assert!(!out.join("results.csv").exists());
    drop(held);
    // A lock left by a killed sweep: taken over with a note, removed at the end.
    std::fs::write(&lock_path, "4000000000\n").unwrap();
    let o = sweep(dir, &file, "out", &[]);
    let err = text(&o.stderr);
    assert!(
        err.contains("took over the lock of pid 4000000000"),
        "{err}"
    );
    assert!(!lock_path.exists());
    // An error after the lock was taken lets it go too.
    let o = wovenform(dir, &["sweep", f, "--out", "out"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!lock_path.exists());
}
