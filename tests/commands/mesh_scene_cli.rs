//! Scenes with STL tools through the binary: a good one runs; each bad tool file or placement
//! is refused with exit code 2 before any solving, naming the file and what is wrong.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use wovenform::core::tools::surface::TriSurface;
use wovenform::stl::{read_surface, write_binary};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_wovenform"))
}

/// The analytic tools of `scene` (with `sets`) written as STL into `dir`, 2 mm triangles.
fn tools(scene: &str, sets: &[&str], dir: &Path) -> (TriSurface, TriSurface) {
    common::written_tools(scene, sets, "2", dir)
}

/// A mesh scene in `dir` naming `punch` and `die` (relative paths), blank `blank` mm.
fn scene(dir: &Path, punch: &str, die: &str, blank: f64) -> PathBuf {
    let path = dir.join("scene.toml");
    let text = format!(
        "[tools]\nkind = \"mesh\"\npunch = \"{punch}\"\ndie = \"{die}\"\n\n[process]\nstroke = 20.0\n\n\
         [blank]\nsize = {blank}\n\n[mesh]\nelement_size = 5.0\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn run(scene: &Path, extra: &[&str]) -> Output {
    bin().arg("run").arg(scene).args(extra).output().unwrap()
}

/// Exit code 2 and a message holding every one of `words`.
fn refused(out: &Output, words: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    for w in words {
        assert!(err.contains(w), "expected {w:?} in: {err}");
    }
}

#[test]
fn a_scene_with_stl_tools_runs_and_writes_its_tools_back() {
    let dir = tempfile::tempdir().unwrap();
    let (punch, _) = tools("hemisphere.toml", &[], dir.path());
    let s = scene(dir.path(), "punch.stl", "die.stl", 120.0);
    let out = run(&s, &["--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["converged"], true);
    // The whole blank is solved (the tools' symmetry is not known), and said so.
    assert_eq!(j["solved_part"], "full");
    let shear = j["max_shear_deg"].as_f64().unwrap();
    assert!(shear > 5.0 && shear < 60.0, "{shear}");
    // tools on a mesh scene writes the surfaces back as read.
    let back = dir.path().join("back");
    let out = bin()
        .arg("tools")
        .arg(&s)
        .arg("--out")
        .arg(&back)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(read_surface(&back.join("punch.stl")).unwrap(), punch);
}

#[test]
fn a_bad_file_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (punch, die) = tools("hemisphere.toml", &[], d);
    let s = scene(d, "bad.stl", "die.stl", 120.0);
    let bad = d.join("bad.stl");
    // Empty.
    std::fs::write(&bad, b"").unwrap();
    refused(&run(&s, &[]), &["tools.punch", "bad.stl", "empty"]);
    // Not an STL: the scene file itself.
    std::fs::copy(&s, &bad).unwrap();
    refused(&run(&s, &[]), &["bad.stl", "not an STL"]);
    // Truncated.
    let bytes = std::fs::read(d.join("punch.stl")).unwrap();
    std::fs::write(&bad, &bytes[..bytes.len() - 30]).unwrap();
    refused(&run(&s, &[]), &["bad.stl", "truncated"]);
    // Enormous: a header announcing six million triangles.
    let mut huge = bytes[..80].to_vec();
    huge.extend(6_000_000u32.to_le_bytes());
    huge.extend(&bytes[84..]);
    std::fs::write(&bad, &huge).unwrap();
    refused(&run(&s, &[]), &["bad.stl", "5 million"]);
    // Open: one triangle missing.
    let mut open = punch.clone();
    open.triangles.pop();
    write_binary(&bad, &open).unwrap();
    refused(&run(&s, &[]), &["bad.stl", "not closed"]);
    // Inside out.
    let mut inverted = punch.clone();
    inverted.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    write_binary(&bad, &inverted).unwrap();
    refused(&run(&s, &[]), &["bad.stl", "inside out"]);
    // Missing.
    let s = scene(d, "punch.stl", "nowhere.stl", 120.0);
    refused(&run(&s, &[]), &["tools.die", "nowhere.stl"]);
    let _ = die;
}

#[test]
fn misplaced_tools_are_refused_before_solving() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (punch, die) = tools("hemisphere.toml", &[], d);
    let s = scene(d, "moved.stl", "die.stl", 120.0);
    // A punch 2 mm above the blank.
    write_binary(&d.join("moved.stl"), &punch.translated([0.0, 0.0, 2.0])).unwrap();
    refused(&run(&s, &[]), &["moved.stl", "lowest point is at z = 2"]);
    // A die 1 mm below the blank's plane.
    let s = scene(d, "punch.stl", "moved.stl", 120.0);
    write_binary(&d.join("moved.stl"), &die.translated([0.0, 0.0, -1.0])).unwrap();
    refused(&run(&s, &[]), &["moved.stl", "highest point is at z = -1"]);
    // A die with no flat face: the punch turned upside down (its tip at z = 0), widened to
    // reach under the whole blank.
    let mut dome = punch.clone();
    dome.vertices
        .iter_mut()
        .for_each(|v| *v = [3.0 * v[0], 3.0 * v[1], -v[2]]);
    dome.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    write_binary(&d.join("moved.stl"), &dome).unwrap();
    refused(&run(&s, &[]), &["moved.stl", "no face in z = 0"]);
    // A blank whose edge lies over the opening.
    let s = scene(d, "punch.stl", "die.stl", 60.0);
    refused(&run(&s, &[]), &["blank.size", "not on the die's face"]);
    // A die key that mesh tools do not take.
    let s = scene(d, "punch.stl", "die.stl", 120.0);
    refused(
        &run(&s, &["--set", "tools.rm=5"]),
        &["tools.rm", "not for tools.kind = \"mesh\""],
    );
}

#[test]
fn a_punch_in_the_die_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A 60 mm box punch with a 3 mm nose over the die of a 20 mm box (its face from 21.5 mm
    // off the centre): the punch's flat nose rests on the die's face.
    let wide = d.join("wide");
    let narrow = d.join("narrow");
    tools("paper-box-open.toml", &["tools.rp=3"], &wide);
    tools(
        "paper-box-open.toml",
        &["tools.side=20", "tools.r=5", "tools.rp=5"],
        &narrow,
    );
    let s = scene(d, "wide/punch.stl", "narrow/die.stl", 170.0);
    refused(
        &run(&s, &[]),
        &[
            "wide/punch.stl",
            "narrow/die.stl",
            "starts inside the die",
            "the punch is 60.0 × 60.0 mm in plan; the die's opening reaches ±",
        ],
    );
    // A 30 mm hemisphere into the die of a 20 mm one: it runs into the die on its way down.
    let big = d.join("big");
    let small = d.join("small");
    tools("hemisphere.toml", &[], &big);
    tools("hemisphere.toml", &["tools.radius=20"], &small);
    let s = scene(d, "big/punch.stl", "small/die.stl", 120.0);
    refused(&run(&s, &[]), &["runs into the die", "mm of stroke"]);
}
