//! Hostile input to the commands as a new user meets them: nothing the user gave is
//! overwritten, a specimen or a stroke out of bounds is refused before any work, a long value
//! is not echoed back whole, a full disk leaves no half file, and a result is computed from
//! what the user gave (the shear law swept, a sweep's own base scene).

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{preset, text, wovenform_in};

fn measured_curve() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/bias-extension/glass_plain_115x230.csv")
}

fn code(o: &Output) -> Option<i32> {
    o.status.code()
}

/// Asserts exit 2 with a message naming each of `words`.
fn refused(o: &Output, words: &[&str]) {
    let err = text(&o.stderr);
    assert_eq!(code(o), Some(2), "stderr: {err}");
    for w in words {
        assert!(err.contains(w), "the message does not name `{w}`: {err}");
    }
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn fit_bias_never_writes_over_the_measured_curve_or_the_users_fabric() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = d.join("bias.csv");
    std::fs::copy(measured_curve(), &data).unwrap();
    std::fs::write(
        d.join("fabric.toml"),
        "[fabric]\nlocking_angle_deg = 55.0\n",
    )
    .unwrap();
    let (data_before, fabric_before) = (bytes(&data), bytes(&d.join("fabric.toml")));
    let quick = ["--refine", "0", "--element-size", "20"];
    let fit = |extra: &[&str]| {
        let args = [&["fit", "bias.csv", "--bias", "230x115"], &quick[..], extra].concat();
        wovenform_in(d, &args)
    };
    // Into the data's own folder, as its folder, through a link, with the user's fabric.
    refused(&fit(&["--out", "."]), &["bias.csv", "measured"]);
    refused(&fit(&["--out", "."]), &["bias.csv"]);
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(d, d.join("again")).unwrap();
        refused(&fit(&["--out", "again"]), &["bias.csv"]);
    }
    std::fs::create_dir(d.join("sc")).unwrap();
    std::fs::copy(d.join("fabric.toml"), d.join("sc/fabric.toml")).unwrap();
    refused(
        &fit(&["--scene", "sc/fabric.toml", "--out", "sc"]),
        &["scene file"],
    );
    assert_eq!(bytes(&d.join("sc/fabric.toml")), fabric_before);
    let scene = ["--scene", "fabric.toml"];
    // A folder holding a fabric.toml that wovenform did not write.
    std::fs::create_dir(d.join("mine")).unwrap();
    std::fs::write(d.join("mine/fabric.toml"), "[fabric]\na = 0.1\n").unwrap();
    refused(
        &fit(&["--out", "mine"]),
        &["mine/fabric.toml", "did not write"],
    );
    assert_eq!(bytes(&d.join("mine/fabric.toml")), b"[fabric]\na = 0.1\n");
    // Without --out: a folder of its own, twice (its own files are replaced).
    for _ in 0..2 {
        let o = fit(&scene);
        assert_eq!(code(&o), Some(0), "{}", text(&o.stderr));
    }
    let made = d.join("out/fit-bias-bias");
    for f in ["bias.csv", "bias.png", "shear.png", "fabric.toml"] {
        assert!(made.join(f).is_file(), "{f} not in {}", made.display());
    }
    assert_eq!(bytes(&data), data_before, "the measured curve was changed");
    assert_eq!(bytes(&d.join("fabric.toml")), fabric_before);
}

#[test]
fn tools_never_write_over_a_scenes_stl_or_a_users_stl() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::copy(preset("double-dome.toml"), d.join("dd.toml")).unwrap();
    std::fs::create_dir(d.join("double-dome")).unwrap();
    for f in ["punch.stl", "die.stl"] {
        std::fs::copy(
            preset(&format!("double-dome/{f}")),
            d.join("double-dome").join(f),
        )
        .unwrap();
    }
    let punch = d.join("double-dome/punch.stl");
    let before = bytes(&punch);
    let o = wovenform_in(d, &["tools", "dd.toml", "--out", "double-dome"]);
    refused(&o, &["punch.stl", "tools.punch"]);
    assert_eq!(bytes(&punch), before);
    // An analytic scene into a folder with a user's (ASCII) STL: refused; into the folder
    // wovenform wrote its own STL files in: replaced.
    std::fs::create_dir(d.join("user")).unwrap();
    let ascii = "solid p\nendsolid p\n";
    std::fs::write(d.join("user/die.stl"), ascii).unwrap();
    let open_box = preset("paper-box-open.toml");
    let o = wovenform_in(d, &["tools", &open_box, "--out", "user"]);
    refused(&o, &["die.stl", "did not write"]);
    assert_eq!(bytes(&d.join("user/die.stl")), ascii.as_bytes());
    // The scene's own STL folder is the user's, even though its files are wovenform's.
    let o = wovenform_in(
        d,
        &["tools", &open_box, "--out", "double-dome", "--spacing", "2"],
    );
    refused(&o, &["double-dome/", "did not write"]);
    assert_eq!(bytes(&punch), before);
    for spacing in ["3", "2"] {
        let o = wovenform_in(
            d,
            &["tools", &open_box, "--out", "ours", "--spacing", spacing],
        );
        assert_eq!(code(&o), Some(0), "{}", text(&o.stderr));
    }
    assert!(d.join("ours/punch.stl").is_file());
}

#[test]
fn run_refuses_an_output_folder_where_it_would_write_over_its_scene() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("r")).unwrap();
    // A scene is read by its contents, whatever its name: here one of the run's outputs.
    let scene = d.join("r/summary.json");
    std::fs::copy(preset("paper-box-open.toml"), &scene).unwrap();
    let before = bytes(&scene);
    let o = wovenform_in(d, &["run", "r/summary.json", "--out", "r"]);
    refused(&o, &["summary.json", "scene file"]);
    assert_eq!(bytes(&scene), before);
    assert_eq!(
        std::fs::read_dir(d.join("r")).unwrap().count(),
        1,
        "nothing written"
    );
}

#[test]
fn a_sweep_never_writes_over_its_own_sweep_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A sweep file is read by its contents, whatever its name: here one of the sweep's outputs.
    let text = format!(
        "base = {:?}\n[sweep]\nr = [5.0]\n",
        preset("paper-box-open.toml")
    );
    std::fs::write(d.join("results.csv"), &text).unwrap();
    let o = wovenform_in(d, &["sweep", "results.csv", "--out", "."]);
    refused(&o, &["results.csv", "sweep file"]);
    assert_eq!(bytes(&d.join("results.csv")), text.as_bytes());
}

#[test]
fn specimens_strokes_and_fit_options_out_of_bounds_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = measured_curve();
    let data = data.to_str().unwrap();
    let start = std::time::Instant::now();
    for (args, words) in [
        (vec!["--bias", "1e9x1"], vec!["--bias length", "10 m"]),
        (vec!["--bias", "230x1e-3"], vec!["elements"]),
        (vec!["--bias", "230x200"], vec!["1.5 times"]),
        (
            vec!["--bias", "230x115", "--refine", "1000000"],
            vec!["--refine"],
        ),
        (
            vec!["--bias", "230x115", "--max-shear", "nan"],
            vec!["--max-shear"],
        ),
        (
            vec!["--bias", "230x115", "--max-shear", "95"],
            vec!["--max-shear"],
        ),
        (
            vec!["--bias", "230x115", "--element-size", "0.01"],
            vec!["elements"],
        ),
    ] {
        let o = wovenform_in(d, &[&["fit", data], &args[..]].concat());
        refused(&o, &words);
    }
    let open_box = preset("paper-box-open.toml");
    let bias = [
        "bias", &open_box, "--length", "1e9", "--width", "1", "--stroke", "1",
    ];
    refused(&wovenform_in(d, &bias), &["--length"]);
    let o = wovenform_in(d, &["run", &open_box, "--set", "process.stroke=1e-9"]);
    refused(&o, &["process.stroke", "0.01 mm"]);
    assert!(
        start.elapsed().as_secs_f64() < 20.0,
        "refusals take no work"
    );
    assert!(!d.join("out").exists(), "nothing is written");
}

#[test]
fn a_long_value_is_quoted_as_an_excerpt() {
    let dir = tempfile::tempdir().unwrap();
    let big = "x".repeat(100_000);
    let ones = vec!["1"; 20_000].join(",");
    let open_box = preset("paper-box-open.toml");
    for set in [
        format!("fabric.a={big}"),
        format!("fabric.a=\"{big}\""),
        format!("{big}=1"),
        format!("fabric.{big}=1"),
        format!("fabric.a=[{ones}]"),
    ] {
        let o = wovenform_in(dir.path(), &["run", &open_box, "--set", &set]);
        refused(&o, &["--set", "characters"]);
        assert!(o.stderr.len() < 1500, "{} bytes of message", o.stderr.len());
    }
    // In a scene file: a long value, and a tool path no file system takes.
    for (name, text) in [
        ("a.toml", format!("[fabric]\na = \"{big}\"\n")),
        (
            "p.toml",
            format!("[tools]\nkind = \"mesh\"\npunch = \"{big}\"\ndie = \"d.stl\"\n"),
        ),
    ] {
        std::fs::write(dir.path().join(name), text).unwrap();
        let o = wovenform_in(dir.path(), &["run", name]);
        refused(&o, &[name, "characters"]);
        assert!(o.stderr.len() < 1500, "{} bytes of message", o.stderr.len());
    }
}

#[test]
fn the_shear_law_is_swept_over_a_base_without_one() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sweep = format!(
        "base = {:?}\n[sweep]\nfabric.shear_moment = [[0.0, 0.0, 0.0], [2.0, 0.0, 20.0]]\n",
        preset("paper-box-open.toml")
    );
    std::fs::write(d.join("law.toml"), sweep).unwrap();
    let args = ["sweep", "law.toml", "--out", "s", "--accuracy", "coarse"];
    let o = wovenform_in(d, &args);
    assert_eq!(code(&o), Some(0), "{}", text(&o.stderr));
    let mut rows = csv::Reader::from_path(d.join("s/results.csv")).unwrap();
    let header = rows.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (law, shear) = (col("fabric.shear_moment"), col("max_shear_deg"));
    let mut by_law: Vec<(String, f64)> = rows
        .records()
        .map(|r| {
            let r = r.unwrap();
            (r[law].to_string(), r[shear].parse().unwrap())
        })
        .collect();
    by_law.sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(by_law.len(), 2);
    // A stiffer shear law shears the fabric less: the law reached the solver.
    assert!(by_law[1].0.starts_with("[2"), "{by_law:?}");
    assert!(by_law[1].1 < by_law[0].1 - 0.1, "{by_law:?}");
}

#[test]
fn a_sweep_reads_its_own_base_scene_and_the_explorer_names_its_base() {
    let embedded = wovenform::study::sweep::embedded::explorer_sweep(&[]).unwrap();
    assert_eq!(embedded.base_file.as_deref(), Some("paper-box-open.toml"));
    // A user's sweep whose base has the preset's name reads the user's file.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("paper-box-open.toml"), "[process]\nstroke = 12.5\n").unwrap();
    std::fs::write(
        d.join("s.toml"),
        "base = \"paper-box-open.toml\"\n[sweep]\nr = [5.0]\n",
    )
    .unwrap();
    let plan = wovenform::study::sweep::Plan::load(&d.join("s.toml"), &[]).unwrap();
    assert_eq!(plan.base_scene.process.stroke, 12.5);
    let source = wovenform::tui::source_of_file(&d.join("s.toml")).unwrap();
    let params = wovenform::tui::params::Parameters::new(source).unwrap();
    assert_eq!(params.plan.base_scene.process.stroke, 12.5);
}

/// A full disk (a 96 kB tmpfs, mounted where the machine lets this test: CI runs as root)
/// fails the run naming the file, and leaves no empty or half file behind.
#[test]
fn a_full_disk_leaves_no_half_file() {
    let dir = tempfile::tempdir().unwrap();
    let full = dir.path().join("full");
    if !crate::common::mount_small_tmpfs(&full, "96k") {
        return;
    }
    let open_box = preset("paper-box-open.toml");
    let args = [
        "run",
        &open_box,
        "--accuracy",
        "coarse",
        "--set",
        "process.stroke=3",
    ];
    let o = wovenform_in(dir.path(), &[&args[..], &["--out", "full"]].concat());
    let files: Vec<(String, u64)> = std::fs::read_dir(&full)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                e.metadata().unwrap().len(),
            )
        })
        .collect();
    let _ = std::process::Command::new("umount").arg(&full).status();
    let err = text(&o.stderr);
    assert_eq!(code(&o), Some(1), "stderr: {err}");
    assert!(
        err.contains("full/") && err.contains("No space left"),
        "{err}"
    );
    assert!(!err.contains("ImageError"), "{err}");
    for (name, len) in &files {
        assert!(*len > 0, "{name} is empty");
        assert!(
            !name.starts_with(".tmp"),
            "{name}: a temporary file is left"
        );
    }
}

/// A named pipe or a device given as a scene, a sweep or a curve is refused at once (before,
/// opening the pipe blocked forever and /dev/zero was read until memory ran out).
#[cfg(unix)]
#[test]
fn special_files_as_inputs_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = d.join("pipe.toml");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo");
    let pipe = fifo.to_str().unwrap();
    for (args, words) in [
        (vec!["run", pipe], vec!["pipe.toml", "named pipe"]),
        (
            vec!["sweep", pipe, "--out", "s"],
            vec!["pipe.toml", "named pipe"],
        ),
        (
            vec!["law", "--scene", pipe, "--eps1", "0", "--eps2", "0"],
            vec!["named pipe"],
        ),
        (vec!["run", "/dev/zero"], vec!["/dev/zero", "device"]),
        (vec!["fit", "/dev/zero"], vec!["/dev/zero", "device"]),
    ] {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_wovenform"))
            .args(&args)
            .current_dir(d)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let start = std::time::Instant::now();
        while child.try_wait().unwrap().is_none() {
            if start.elapsed().as_secs() > 20 {
                let _ = child.kill();
                panic!("{args:?}: still running after 20 s");
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        refused(&child.wait_with_output().unwrap(), &words);
    }
}

#[test]
fn ladders_and_repetitions_out_of_bounds_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let open_box = preset("paper-box-open.toml");
    let converge = |extra: &[&str]| {
        let args = [&["converge", &open_box, "--out", "cv"], extra].concat();
        wovenform_in(d, &args)
    };
    // A rung too fine for this machine's memory (0.01 mm: 2.9e8 elements), a step count past
    // the solver's budget, repetitions of nothing or of forever.
    refused(
        &converge(&["--sizes", "5,1,0.01"]),
        &["--sizes 0.01", "memory"],
    );
    refused(
        &converge(&["--steps", "4,8,1000000000"]),
        &["--steps", "budget"],
    );
    for reps in ["0", "1000000000"] {
        refused(
            &wovenform_in(d, &["bench", "--repetitions", reps]),
            &["--repetitions"],
        );
    }
    assert!(!d.join("cv").exists(), "nothing is written");
}

/// Found by a second hostile pass: a user's summary.json in --out, a stroke deeper than the
/// blank, a path of 120 kB quoted back, standard output that cannot be written.
#[test]
fn a_second_pass_of_hostile_cases() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let open_box = preset("paper-box-open.toml");
    std::fs::create_dir(d.join("u")).unwrap();
    std::fs::write(d.join("u/summary.json"), "mine").unwrap();
    let o = wovenform_in(d, &["run", &open_box, "--out", "u"]);
    refused(&o, &["u/summary.json", "did not write"]);
    assert_eq!(bytes(&d.join("u/summary.json")), b"mine");
    let deep = wovenform_in(d, &["run", &open_box, "--set", "process.stroke=1e20"]);
    refused(&deep, &["process.stroke = 1e20", "longest side"]);
    let long = vec!["d".repeat(200); 600].join("/");
    let o = wovenform_in(d, &["run", &long]);
    assert_eq!(code(&o), Some(2));
    assert!(o.stderr.len() < 3000, "{} bytes of message", o.stderr.len());
    let full = std::fs::File::create("/dev/full");
    if let Ok(full) = full {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_wovenform"))
            .args(["law", "--eps1", "0", "--eps2", "0"])
            .stdout(full)
            .output()
            .unwrap();
        let err = text(&o.stderr);
        assert_eq!(code(&o), Some(1), "{err}");
        assert!(
            err.contains("standard output") && !err.contains("panicked"),
            "{err}"
        );
    }
}
