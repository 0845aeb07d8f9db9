//! `wovenform tools` as a user runs it: the real binary writes the scene's punch and die as
//! binary STL files that read back as closed tools in the drawing's frame.

use crate::common;
use common::{preset, text, wovenform_in};
use wovenform::stl::read_surface;

#[test]
fn the_presets_tools_are_written_and_read_back() {
    for name in ["paper-box-open.toml", "hemisphere.toml"] {
        let dir = tempfile::tempdir().unwrap();
        let scene = preset(name);
        let o = wovenform_in(
            dir.path(),
            &["tools", &scene, "--out", "stl", "--spacing", "2"],
        );
        let out = text(&o.stdout);
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        for tool in ["punch", "die"] {
            let path = dir.path().join("stl").join(format!("{tool}.stl"));
            let surface = read_surface(&path).unwrap_or_else(|e| panic!("{e}"));
            let line = format!(
                "stl/{tool}.stl: {} triangles (spacing 2 mm)",
                surface.triangles.len()
            );
            assert!(out.contains(&line), "`{line}` not in: {out}");
            let (lo, hi) = surface.bounds();
            if tool == "punch" {
                assert!(lo[2].abs() < 1e-6, "{name}: the punch's lowest z {}", lo[2]);
                assert!(hi[2] > 20.0, "{name}: the punch's top z {}", hi[2]);
            } else {
                assert!(hi[2].abs() < 1e-9, "{name}: the die's highest z {}", hi[2]);
                assert!(lo[2] < -20.0, "{name}: the die's bottom z {}", lo[2]);
            }
        }
    }
}

#[test]
fn bad_input_exits_2_naming_the_file_or_option() {
    let dir = tempfile::tempdir().unwrap();
    let scene = preset("hemisphere.toml");
    let cases: [(&[&str], &[&str]); 4] = [
        (
            &["tools", "absent.toml", "--out", "o"],
            &["absent.toml", "cannot read the scene file"],
        ),
        (
            &["tools", &scene, "--out", "o", "--spacing", "0"],
            &["--spacing 0", "positive length"],
        ),
        (
            &["tools", &scene, "--out", "o", "--spacing", "8"],
            &["--spacing 8 mm", "smallest radius (5 mm)"],
        ),
        (
            &["tools", &scene, "--out", "o", "--spacing", "0.001"],
            &["--spacing 0.001 mm", "grid points", "expected --spacing ≥"],
        ),
    ];
    for (args, words) in cases {
        let o = wovenform_in(dir.path(), args);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        for w in words {
            assert!(err.contains(w), "{args:?}: `{w}` not in: {err}");
        }
    }
    assert!(
        !dir.path().join("o").exists(),
        "nothing written on bad input"
    );
}
