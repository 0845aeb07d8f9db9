//! Mesh scenes a hostile (or unlucky) user runs through the binary: tools in other units, a
//! die whose tables would not fit in memory, a punch through itself, files that are not files,
//! a tool file written anew under a sweep being resumed. Each is refused with exit code 2
//! naming the key and the file, quickly (before any solving, never by a crash), and a run
//! that cannot end is not waited on.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use wovenform::core::tools::surface::TriSurface;
use wovenform::stl::write_binary;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_wovenform"))
}

/// Runs `cmd` in `dir`, killed after `limit` (then the test fails).
fn within(mut cmd: Command, dir: &Path, limit: Duration) -> (Output, Duration) {
    let start = Instant::now();
    let mut child = cmd
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            child.kill().unwrap();
            let out = child.wait_with_output().unwrap();
            panic!(
                "{cmd:?} still running after {limit:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    (child.wait_with_output().unwrap(), start.elapsed())
}

fn tools(scene: &str, sets: &[&str], spacing: &str, dir: &Path) -> (TriSurface, TriSurface) {
    common::written_tools(scene, sets, spacing, dir)
}

/// A mesh scene in `dir`: `punch` and `die` (relative paths), blank `blank` mm, 20 mm of
/// stroke, 5 mm elements, and `more` lines.
fn scene(dir: &Path, punch: &str, die: &str, blank: f64, more: &str) -> PathBuf {
    let path = dir.join("scene.toml");
    let text = format!(
        "[tools]\nkind = \"mesh\"\npunch = \"{punch}\"\ndie = \"{die}\"\n{more}\n\n\
         [process]\nstroke = 20.0\n\n[blank]\nsize = {blank}\n\n[mesh]\nelement_size = 5.0\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs `scene` and expects exit code 2 within 30 s and a message holding every one of
/// `words`; returns the message.
fn refused(dir: &Path, scene: &Path, words: &[&str]) -> String {
    let mut cmd = bin();
    cmd.arg("run").arg(scene).args(["--out", "out"]);
    let (out, took) = within(cmd, dir, Duration::from_secs(30));
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{err}");
    for w in words {
        assert!(err.contains(w), "expected {w:?} in: {err}");
    }
    assert!(
        took < Duration::from_secs(20),
        "refused only after {took:?}: {err}"
    );
    err
}

fn scaled(s: &TriSurface, f: f64) -> TriSurface {
    TriSurface {
        vertices: s.vertices.iter().map(|v| v.map(|x| x * f)).collect(),
        triangles: s.triangles.clone(),
    }
}

#[test]
fn tools_in_other_units_are_refused_naming_the_likely_unit() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // The open box's tools (a 60 mm punch 30 mm tall, a 200 mm die) for a 170 mm blank.
    let (punch, die) = tools("paper-box-open.toml", &["process.stroke=20"], "2", d);
    let cases: [(&str, &TriSurface, f64, &[&str]); 6] = [
        (
            "tools.punch",
            &punch,
            0.001,
            &["0.060 × 0.060 mm", "one element", "metres"],
        ),
        (
            "tools.punch",
            &punch,
            1.0 / 25.4,
            &["2.4 × 2.4 mm", "inches (×25.4"],
        ),
        (
            "tools.punch",
            &punch,
            1000.0,
            &["60000 × 60000 mm", "larger than the blank"],
        ),
        (
            "tools.die",
            &die,
            0.001,
            &["smaller than the blank", "metres (×1000"],
        ),
        // Far too large: its face is nowhere under the blank (this once allocated 27.8 TB).
        (
            "tools.die",
            &die,
            1000.0,
            &["opening is wider than the blank", "micrometres"],
        ),
        (
            "tools.die",
            &die,
            100.0,
            &["opening is wider than the blank", "20000 × 20000"],
        ),
    ];
    for (key, tool, factor, words) in cases {
        write_binary(&d.join("scaled.stl"), &scaled(tool, factor)).unwrap();
        let s = if key == "tools.punch" {
            scene(d, "scaled.stl", "die.stl", 170.0, "")
        } else {
            scene(d, "punch.stl", "scaled.stl", 170.0, "")
        };
        let words = [&[key, "scaled.stl", "STL has no units"][..], words].concat();
        refused(d, &s, &words);
    }
    // The tools as written run (the checks pass what is right).
    let s = scene(d, "punch.stl", "die.stl", 170.0, "");
    let mut cmd = bin();
    cmd.arg("run")
        .arg(&s)
        .args(["--out", "ok", "--set", "process.stroke=2"]);
    let (out, _) = within(cmd, d, Duration::from_secs(120));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn tables_too_large_for_memory_are_refused_before_allocating() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // A 3 m blank on a 3.03 m die plate: at a 0.05 mm lattice its page table alone would be
    // about a terabyte.
    tools("paper-box-open.toml", &["blank.size=3000"], "10", d);
    let s = scene(d, "punch.stl", "die.stl", 3000.0, "lattice = 0.05");
    std::fs::write(
        &s,
        std::fs::read_to_string(&s)
            .unwrap()
            .replace("5.0\n", "20.0\n"),
    )
    .unwrap();
    let err = refused(
        d,
        &s,
        &[
            "tools.die",
            "die.stl",
            "would need about",
            "at most",
            "tools.lattice ≥",
        ],
    );
    assert!(err.contains("TiB"), "{err}");
}

#[test]
fn a_punch_through_itself_is_refused_naming_it_and_where() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let (punch, _) = tools("hemisphere.toml", &[], "2", d);
    // The hemisphere and a block overlapping its top: two solids in one file.
    let mut soup = punch.soup();
    let (lo, hi) = ([-10.0, -10.0, 20.0], [10.0, 10.0, 40.0]);
    soup.extend(wovenform::core::tools::surface::box_soup(lo, hi));
    write_binary(&d.join("two.stl"), &TriSurface::from_soup(&soup).unwrap()).unwrap();
    let s = scene(d, "two.stl", "die.stl", 120.0, "");
    let err = refused(
        d,
        &s,
        &[
            "tools.punch",
            "two.stl",
            "passes through itself",
            "cross near (",
        ],
    );
    assert!(!err.contains("Newton"), "{err}");
}

#[test]
fn tool_paths_that_are_not_files_are_refused_without_waiting() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    tools("hemisphere.toml", &[], "2", d);
    let fifo = d.join("fifo.stl");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let s = scene(d, "fifo.stl", "die.stl", 120.0, "");
    refused(d, &s, &["tools.punch", "fifo.stl", "named pipe (FIFO)"]);
    let s = scene(d, "punch.stl", "/dev/zero", 120.0, "");
    refused(d, &s, &["tools.die", "/dev/zero", "character device"]);
    let s = scene(d, ".", "die.stl", 120.0, "");
    refused(d, &s, &["tools.punch", "a directory"]);
    let s = scene(d, "  ", "die.stl", 120.0, "");
    refused(d, &s, &["tools.punch", "the path of an STL file"]);
    for lattice in ["0.0", "1e-9", "1e9", "nan", "-1.0"] {
        let s = scene(
            d,
            "punch.stl",
            "die.stl",
            120.0,
            &format!("lattice = {lattice}"),
        );
        refused(d, &s, &["tools.lattice", "0.05 to 5 mm"]);
    }
}

#[test]
fn resuming_a_sweep_whose_tool_file_was_written_anew_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let (punch, _) = tools("hemisphere.toml", &[], "2", d);
    scene(d, "punch.stl", "die.stl", 120.0, "");
    let sweep = d.join("grid.toml");
    let grid = "base = \"scene.toml\"\n\n[scene]\nprocess.stroke = 3.0\n\n[sweep]\nfriction = [0.1, 0.2]\n";
    std::fs::write(&sweep, grid).unwrap();
    let run = |extra: &[&str]| {
        let mut cmd = bin();
        cmd.args(["sweep", "grid.toml", "--out", "out"]).args(extra);
        within(cmd, d, Duration::from_secs(300)).0
    };
    let o = run(&[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Resuming with the same files runs nothing.
    let o = run(&["--resume"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The punch written anew, 10 % narrower: same path, other contents.
    let mut narrower = punch.clone();
    narrower
        .vertices
        .iter_mut()
        .for_each(|v| *v = [0.9 * v[0], 0.9 * v[1], v[2]]);
    write_binary(&d.join("punch.stl"), &narrower).unwrap();
    let o = run(&["--resume"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for w in [
        "another base scene",
        "tools.punch",
        "punch.stl",
        "written anew",
    ] {
        assert!(err.contains(w), "expected {w:?} in: {err}");
    }
    // The rows are those of the first punch only: two designs, once each.
    let csv = std::fs::read_to_string(d.join("out/results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
}
