//! What `wovenform sweep` says before it starts: how many designs and roughly how long, and
//! how many workers it really starts when asked for more than there are designs or cores.

mod common;
use common::{text, wovenform_in as wovenform};

#[test]
fn a_sweep_says_how_many_designs_and_how_long_and_starts_no_idle_workers() {
    let dir = tempfile::tempdir().unwrap();
    let base = common::preset("paper-box-open.toml");
    let file = dir.path().join("s.toml");
    std::fs::write(
        &file,
        format!(
            "base = {base:?}\n\n[scene]\nmesh.element_size = 5.0\nprocess.stroke = 4.0\nblank.size = 140.0\n\n[sweep]\nr = [5.0, 10.0]\n"
        ),
    )
    .unwrap();
    let o = wovenform(
        dir.path(),
        &[
            "sweep",
            file.to_str().unwrap(),
            "--out",
            "o",
            "--jobs",
            "1000",
        ],
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("--jobs 1000: 2 designs"), "{err}");
    assert!(err.contains("2 designs to run, roughly"), "{err}");
    // One design: no plural.
    let one = dir.path().join("one.toml");
    std::fs::write(
        &one,
        format!("base = {base:?}\n\n[scene]\nmesh.element_size = 5.0\nprocess.stroke = 4.0\nblank.size = 140.0\n\n[sweep]\nr = [5.0]\n"),
    )
    .unwrap();
    let o = wovenform(dir.path(), &["sweep", one.to_str().unwrap(), "--out", "p"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("1 design to run"),
        "{}",
        text(&o.stderr)
    );
    assert!(
        text(&o.stdout).contains("1 design run in"),
        "{}",
        text(&o.stdout)
    );
    // A value given twice is refused before anything runs.
    let twice = dir.path().join("twice.toml");
    std::fs::write(
        &twice,
        format!("base = {base:?}\n\n[sweep]\nr = [5.0, 5]\n"),
    )
    .unwrap();
    let o = wovenform(
        dir.path(),
        &["sweep", twice.to_str().unwrap(), "--out", "q"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("5 is given twice"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn a_resume_on_another_scene_names_what_changed() {
    let dir = tempfile::tempdir().unwrap();
    let base = common::preset("paper-box-open.toml");
    let file = dir.path().join("s.toml");
    std::fs::write(
        &file,
        format!("base = {base:?}\n\n[scene]\nprocess.stroke = 4.0\nblank.size = 140.0\n\n[sweep]\nr = [5.0]\n"),
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let o = wovenform(
        dir.path(),
        &["sweep", f, "--out", "o", "--accuracy", "coarse"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let o = wovenform(dir.path(), &["sweep", f, "--out", "o", "--resume"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    // It used to say "(X with Y; now X with Y)": both sides the same.
    assert!(
        text(&o.stderr).contains("mesh.element_size: 5.0 → 2.5"),
        "{}",
        text(&o.stderr)
    );
}
