//! Shared by the test files: a small deterministic random generator (no extra dependency).
#![allow(dead_code)]

/// A linear congruential generator: the same sequence on every machine.
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The recorded residual histories of a run's load steps that converged.
pub fn accepted_residuals(
    stats: &wovenform::core::solver::SolveStats,
) -> impl Iterator<Item = &Vec<f64>> {
    (stats.residuals.iter().enumerate())
        .filter(|(s, _)| stats.accepted(*s))
        .map(|(_, h)| h)
}

use std::path::Path;
use std::process::{Command, Output};

/// The path of a preset, as a command-line argument.
pub fn preset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("presets")
        .join(name)
        .to_str()
        .expect("a UTF-8 path")
        .to_string()
}

/// A preset's drawing problem with `--set`-style overrides (`"tools.r=7"`).
pub fn preset_problem(name: &str, sets: &[&str]) -> wovenform::core::drawing::DrawingProblem {
    let sets: Vec<wovenform::scene::Override> = sets
        .iter()
        .map(|s| s.parse().expect("a key=value override"))
        .collect();
    wovenform::scene::Scene::load(Some(preset(name).as_ref()), &sets)
        .expect("the preset loads")
        .to_problem()
}

/// Runs the real binary in `dir` with `args`.
pub fn wovenform_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wovenform"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the wovenform binary runs")
}

/// Program output as text.
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The analytic tools of the preset `scene` (with `sets`) written as STL into `dir` by
/// `wovenform tools` on a grid of `spacing` mm, and read back.
pub fn written_tools(
    scene: &str,
    sets: &[&str],
    spacing: &str,
    dir: &Path,
) -> (
    wovenform::core::tools::surface::TriSurface,
    wovenform::core::tools::surface::TriSurface,
) {
    std::fs::create_dir_all(dir).expect("the tools' folder");
    let scene = preset(scene);
    let mut args = vec![
        "tools",
        &scene,
        "--out",
        dir.to_str().expect("a UTF-8 path"),
    ];
    args.extend(["--spacing", spacing]);
    for s in sets {
        args.extend(["--set", s]);
    }
    let out = wovenform_in(dir, &args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let read = |name: &str| wovenform::stl::read_surface(&dir.join(name)).unwrap();
    (read("punch.stl"), read("die.stl"))
}

/// Writes `bytes` as `dir/name`; returns its path.
pub fn write_file(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// The message of reading the STL at `path` as a tool, which must fail within 20 s (a file
/// that blocks fails the test rather than hanging it), naming the file.
pub fn stl_refusal(path: &Path) -> String {
    let (tx, rx) = std::sync::mpsc::channel();
    let p = path.to_path_buf();
    std::thread::spawn(move || {
        let read = wovenform::stl::read_surface(&p);
        let _ = tx.send(read.map(|_| ()).map_err(|e| e.to_string()));
    });
    let message = rx
        .recv_timeout(std::time::Duration::from_secs(20))
        .unwrap_or_else(|_| panic!("reading {} did not end within 20 s", path.display()))
        .expect_err("the file must be refused");
    assert!(
        message.contains(&path.display().to_string()),
        "the file is not named: {message}"
    );
    message
}

/// Asserts that `message` holds each of `words`.
pub fn assert_says(message: &str, words: &[&str]) {
    for w in words {
        assert!(message.contains(w), "`{w}` not in: {message}");
    }
}

/// The largest entry of `v`.
pub fn largest(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::MIN, f64::max)
}

/// Asserts that `changed` moved none of `reference`'s figures by a tenth of the standard level's
/// band (0.12° of max shear, 0.5 % of the punch force, 3.5 % of the max tension); returns the
/// moves (°, and shares of the force and the tension).
pub fn moves_no_figure(
    reference: &wovenform::core::drawing::DrawingResult,
    changed: &wovenform::core::drawing::DrawingResult,
) -> (f64, f64, f64) {
    let shear = (largest(&changed.shear_deg) - largest(&reference.shear_deg)).abs();
    assert!(shear <= 0.12, "max shear moved {shear:.4}°");
    let force = (changed.punch_force_n / reference.punch_force_n - 1.0).abs();
    assert!(force <= 0.005, "punch force moved {:.3} %", 100.0 * force);
    let tension = (changed.max_tension_n() / reference.max_tension_n() - 1.0).abs();
    assert!(
        tension <= 0.035,
        "max tension moved {:.3} %",
        100.0 * tension
    );
    (shear, force, tension)
}

/// The open box with tools and friction off the paper's grid and off the presets (8/13/6 mm,
/// μ 0.22): the design the solver's ways of ending or shaping a step are judged on.
pub fn off_grid_box() -> wovenform::core::drawing::DrawingProblem {
    preset_problem(
        "paper-box-open.toml",
        &[
            "tools.r=8",
            "tools.rp=13",
            "tools.rm=6",
            "process.friction=0.22",
        ],
    )
}

/// Mounts a tmpfs of `size` (e.g. `"96k"`) on the new folder `dir`, for a full disk; `false`
/// where this user cannot mount (CI runs as root and can), after saying the check is skipped.
pub fn mount_small_tmpfs(dir: &Path, size: &str) -> bool {
    std::fs::create_dir(dir).unwrap();
    let mounted = std::process::Command::new("mount")
        .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
        .arg(dir)
        .output()
        .is_ok_and(|o| o.status.success());
    if !mounted {
        eprintln!("not checked: this user cannot mount a small tmpfs (CI runs as root and does)");
    }
    mounted
}
