//! Bad scenes given to `wovenform run`: exit code 2 before any solving, and a message on
//! stderr that names the file (or the `--set`), the key and what was expected.

use std::process::{Command, Output};

use crate::common;
use common::preset;

fn wovenform(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wovenform"))
        .args(args)
        .output()
        .expect("the wovenform binary runs")
}

/// Runs `run SCENE args…` and checks exit code 2, nothing on stdout, and every word on stderr.
fn assert_rejected(scene: &str, args: &[&str], must_name: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = wovenform(&[&["run", scene, "--out", out.to_str().unwrap()][..], args].concat());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: stderr: {err}");
    assert!(o.stdout.is_empty(), "{args:?}: printed a result");
    assert!(!out.exists(), "{args:?}: wrote files");
    for word in must_name {
        assert!(
            err.contains(word),
            "{args:?}: stderr does not name `{word}`: {err}"
        );
    }
}

/// A scene file in a temporary folder (kept alive by the returned guard).
fn scene_file(text: &str) -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let s = path.to_str().unwrap().to_string();
    (dir, s)
}

#[test]
fn bad_toml_names_the_file_and_line() {
    let (_d, f) = scene_file("[tools]\nr = 5\nrp = = 6\n");
    assert_rejected(&f, &[], &[&f, "not valid TOML", "line 3"]);
}

#[test]
fn unknown_keys_and_sections_are_named() {
    let (_d, f) = scene_file("[tools]\nr = 5\nnose = 6\n");
    assert_rejected(&f, &[], &[&f, "tools.nose", "unknown key", "rp"]);
    let (_d, f) = scene_file("[tooling]\nr = 5\n");
    assert_rejected(&f, &[], &[&f, "tooling", "unknown section"]);
    let open = preset("paper-box-open.toml");
    assert_rejected(
        &open,
        &["--set", "process.speed=3"],
        &["--set process.speed=3", "process.speed", "unknown key"],
    );
    // A section only the --set brings in is blamed on the --set, not on the file.
    assert_rejected(
        &open,
        &["--set", "nosuch.key=1"],
        &["error: --set nosuch.key=1: nosuch: unknown section"],
    );
}

#[test]
fn negative_radius() {
    let (_d, f) = scene_file("[tools]\nr = -2\n");
    assert_rejected(
        &f,
        &[],
        &[
            &f,
            "tools.r = -2",
            "expected a punch corner radius r > 0 mm",
        ],
    );
    let open = preset("paper-box-open.toml");
    assert_rejected(
        &open,
        &["--set", "tools.rm=-1"],
        &["--set tools.rm=-1", "tools.rm = -1", "> 0 mm"],
    );
    let hemi = preset("hemisphere.toml");
    assert_rejected(&hemi, &["--set", "tools.radius=-30"], &["tools.radius"]);
}

#[test]
fn rp_larger_than_the_punch_allows() {
    let open = preset("paper-box-open.toml");
    assert_rejected(
        &open,
        &["--set", "tools.rp=35"],
        &[
            "--set tools.rp=35",
            "tools.rp = 35",
            "rp larger than the punch allows",
            "side/2 = 30 mm",
        ],
    );
    assert_rejected(
        &open,
        &["--set", "tools.r=30"],
        &["tools.r = 30", "r larger than the punch allows"],
    );
}

#[test]
fn blank_barely_larger_than_the_die_opening() {
    let open = preset("paper-box-open.toml");
    // Opening 63 mm, rm 10 mm: the blank needs more than 83 mm.
    assert_rejected(
        &open,
        &["--set", "blank.size=[140,80]"],
        &[
            "--set blank.size=[140,80]",
            "blank.size = [140, 80]",
            "blank barely larger than the die opening",
            "[83, 83] mm",
        ],
    );
    let (_d, f) = scene_file("[tools]\nkind = \"hemisphere\"\nradius = 30\n[blank]\nsize = 70\n");
    assert_rejected(&f, &[], &[&f, "barely larger than the die opening"]);
}

#[test]
fn friction_and_process_bounds() {
    let open = preset("paper-box-open.toml");
    assert_rejected(
        &open,
        &["--set", "process.friction=-0.1"],
        &[
            "process.friction = -0.1",
            "friction coefficient μ in [0, 1]",
        ],
    );
    assert_rejected(
        &open,
        &["--set", "process.holder_pressure=80"],
        &["process.holder_pressure = 80", "[0, 50] MPa"],
    );
    assert_rejected(
        &open,
        &["--set", "process.stroke=0"],
        &["process.stroke = 0", "at least 0.01 mm"],
    );
    assert_rejected(
        &open,
        &["--set", "mesh.element_size=50"],
        &["mesh.element_size = 50", "blank/4 = 42.5 mm"],
    );
    let ellipsoid = preset("paper-ellipsoid.toml");
    assert_rejected(
        &ellipsoid,
        &["--set", "process.stroke=25"],
        &["process.stroke = 25", "az = 20 mm"],
    );
}

#[test]
fn wrong_types_and_kinds() {
    let open = preset("paper-box-open.toml");
    assert_rejected(
        &open,
        &["--set", "tools.kind=\"cone\""],
        &["tools.kind", "box", "ellipsoid", "hemisphere"],
    );
    assert_rejected(&open, &["--set", "tools.r=\"big\""], &["tools.r"]);
    assert_rejected(
        &open,
        &["--set", "tools.axes=[30,20,10]"],
        &["tools.axes", "only for tools.kind = \"ellipsoid\""],
    );
    assert_rejected(
        &open,
        &["--set", "tools.r=oops"],
        &["tools.r", "TOML literal"],
    );
    let missing = "/nonexistent-wovenform/scene.toml";
    assert_rejected(missing, &[], &[missing, "cannot read"]);
}

#[test]
fn set_edges_are_named_and_numbers_stay_short() {
    let open = preset("paper-box-open.toml");
    // Everything after a line break in a --set used to be dropped silently.
    assert_rejected(
        &open,
        &["--set", "tools.r=7.5\ntools.rp=3"],
        &["--set tools.r=7.5\\ntools.rp=3", "line break"],
    );
    // Switching a box scene to a hemisphere would drop its r, rp and side.
    assert_rejected(
        &open,
        &["--set", "tools.kind=\"hemisphere\""],
        &["--set tools.kind", "drop the scene file's tools."],
    );
    // 1e308 is written as 1e308, not as 309 digits.
    assert_rejected(&open, &["--set", "tools.r=1e308"], &["tools.r = 1e308:"]);
    assert_rejected(
        &open,
        &["--set", "mesh.element_size=1e-300"],
        &["mesh.element_size = 1e-300 mm", "unbounded memory"],
    );
    // A fabric whose yarns start further from 90° than the locking angle is locked already.
    assert_rejected(
        &open,
        &["--set", "fabric.yarn_angle_deg=1"],
        &["fabric.yarn_angle_deg = 1", "30 and 150 degrees"],
    );
    let o = wovenform(&["run", &open, "--set", "tools.r=1e308"]);
    assert!(
        o.stderr.len() < 400,
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn a_mesh_too_large_for_the_machine_is_refused_before_any_allocation() {
    // 0.001 mm elements on the 170 mm blank: 7e9 elements, tens of TiB. Refused with the size,
    // the memory it would need and what would fit, before a byte of the mesh exists (the
    // process's peak memory stays that of an idle run).
    let open = preset("paper-box-open.toml");
    assert_rejected(
        &open,
        &["--set", "mesh.element_size=0.001"],
        &[
            "--set mesh.element_size=0.001",
            "mesh.element_size = 0.001 mm",
            "elements",
            "TiB",
            "expected mesh.element_size ≥",
        ],
    );
    assert_rejected(
        &open,
        &["--set", "blank.size=1e6"],
        &["--set blank.size=1e6", "of memory", "on this machine"],
    );
}

#[test]
fn shear_law_bounds() {
    let open = preset("paper-box-open.toml");
    // A moment that falls past some angle (k3 strongly negative) has no unique answer.
    assert_rejected(
        &open,
        &["--set", "fabric.shear_moment=[0.05, -1.0, 0.0]"],
        &["fabric.shear_moment", "rising"],
    );
    assert_rejected(
        &open,
        &["--set", "fabric.shear_moment=[-0.01, 0.0, 0.0]"],
        &["fabric.shear_moment", "k1 ≥ 0"],
    );
    assert_rejected(
        &open,
        &["--set", "fabric.shear_locking=true"],
        &["fabric.shear_locking", "fabric.shear_moment"],
    );
}
