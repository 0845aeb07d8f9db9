//! `wovenform cantilever`: the heavy cantilever of a scene's fabric against `w L⁴/(8B)`, and
//! its refusals (no rigidity, no mass, the woven law, bad keys) with exit 2 before any work.

use crate::common::{text, wovenform_in, write_file};

const FABRIC: &str =
    "[fabric]\nundulation = false\nbending_rigidity = [0.08, 0.08]\nareal_mass = 300.0\n";

#[test]
fn the_overhang_test_falls_as_the_small_deflection_closed_form() {
    let d = tempfile::tempdir().unwrap();
    write_file(d.path(), "glass.toml", FABRIC.as_bytes());
    let out = wovenform_in(
        d.path(),
        &["cantilever", "glass.toml", "--length", "20", "--json"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let w = 300.0 * 1e-9 * 9.80665;
    let closed = w * 20f64.powi(4) / (8.0 * 0.08);
    let tip = j["tip_deflection_mm"].as_f64().unwrap();
    assert!(
        (tip / closed - 1.0).abs() < 0.02,
        "{tip} mm against {closed} mm"
    );
    // Peirce's formula, read back from a small chord, gives the scene's B within 1 %.
    let b = j["peirce_rigidity_nmm"].as_f64().unwrap();
    assert!((b / 0.08 - 1.0).abs() < 0.01, "{b}");
    // The text names the bending length with its unit; the picture is written where it says.
    let args = ["cantilever", "glass.toml", "--length", "20", "--out", "cv"];
    let out = wovenform_in(d.path(), &args);
    let said = text(&out.stdout);
    assert!(said.contains("bending length c = 30.07 mm"), "{said}");
    assert!(said.contains("cantilever.png"), "{said}");
    let png = std::fs::read(d.path().join("cv/cantilever.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
}

#[test]
fn a_fabric_without_bending_or_mass_is_refused_with_exit_2_and_the_woven_law_bends() {
    let d = tempfile::tempdir().unwrap();
    let cases = [
        (
            "[fabric]\nundulation = false\nareal_mass = 300.0\n",
            "fabric.bending_rigidity",
        ),
        (
            "[fabric]\nundulation = false\nbending_rigidity = [0.08, 0.08]\n",
            "fabric.areal_mass",
        ),
        (
            "[fabric]\nundulation = false\nbending_rigidity = [-1.0, 0.08]\n",
            "fabric.bending_rigidity",
        ),
        (
            "[fabric]\nundulation = false\nbending_rigidity = [0.1, 0.1]\nareal_mass = -3.0\n",
            "fabric.areal_mass",
        ),
        (
            "[fabric]\nundulation = false\nbending_rigidity = [0.1, 0.1]\ncompressive_stiffness = [1e6, 1.0]\n",
            "fabric.compressive_stiffness",
        ),
        (
            "[fabric]\nundulation = false\ncompressive_stiffness = [1.0, 1.0]\n",
            "fabric.compressive_stiffness",
        ),
        (
            "[fabric]\nundulation = false\nbending_rigidity = [0.1, 0.1]\nareal_mass = 300.0\n\
             [mesh]\nsymmetry = \"quarter\"\n",
            "mesh.symmetry",
        ),
    ];
    for (scene, key) in cases {
        write_file(d.path(), "s.toml", scene.as_bytes());
        let out = wovenform_in(d.path(), &["cantilever", "s.toml", "--length", "20"]);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{scene}: {err}");
        assert!(
            err.contains(key) && err.contains("s.toml"),
            "{scene}: {err}"
        );
    }
    // The woven law (the default) bends too: its compressive branch stands beside the crimp.
    write_file(
        d.path(),
        "s.toml",
        b"[fabric]\nbending_rigidity = [0.08, 0.08]\nareal_mass = 300.0\n",
    );
    let out = wovenform_in(
        d.path(),
        &["cantilever", "s.toml", "--length", "20", "--json"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
}

#[test]
fn a_strip_too_coarse_too_large_or_without_a_warp_rigidity_is_refused_naming_what() {
    let d = tempfile::tempdir().unwrap();
    write_file(d.path(), "glass.toml", FABRIC.as_bytes());
    let cases: [(&[&str], &str); 6] = [
        // Elements as long as the overhang would read the tip 25 % off the closed form.
        (
            &["--length", "20", "--element-size", "30"],
            "--element-size of at most 2 mm",
        ),
        (&["--length", "0.5"], "at most 0.05 mm"),
        (&["--length", "1e9"], "--length 1000000000"),
        (
            &["--length", "20", "--element-size", "1e-4"],
            "expected at most 200000",
        ),
        (&["--length", "20", "--width", "1e6"], "--width 1000000"),
        (
            &[
                "--length",
                "20",
                "--set",
                "fabric.bending_rigidity=[0,0.08]",
            ],
            "--set fabric.bending_rigidity=[0,0.08]: fabric.bending_rigidity",
        ),
    ];
    for (args, said) in cases {
        let mut all = vec!["cantilever", "glass.toml"];
        all.extend_from_slice(args);
        let out = wovenform_in(d.path(), &all);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(said), "{args:?}: {err}");
    }
    assert!(!d.path().join("out").exists(), "refused before any work");
    // At the fewest elements allowed the tip is still within the bound's 1 % (and 1.5 % of
    // the small-deflection closed form, which the fine mesh meets to 0.05 %).
    let args = [
        "cantilever",
        "glass.toml",
        "--length",
        "20",
        "--element-size",
        "2",
    ];
    let out = wovenform_in(d.path(), &[&args[..], &["--json"]].concat());
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let closed = 300.0 * 1e-9 * 9.80665 * 20f64.powi(4) / (8.0 * 0.08);
    let tip = j["tip_deflection_mm"].as_f64().unwrap();
    assert!(
        (tip / closed - 1.0).abs() < 0.015,
        "{tip} mm against {closed} mm"
    );
}
