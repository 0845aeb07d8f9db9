//! What `wovenform sweep` says before it starts: how many designs and roughly how long, and
//! how many workers it really starts when asked for more than there are designs or cores.

use crate::common;
use common::{text, wovenform_in as wovenform};

/// A sweep file `name` in `dir` over the open-box preset: `scene` under [scene] (empty: none),
/// `sweep` under [sweep].
fn sweep_file(dir: &std::path::Path, name: &str, scene: &str, sweep: &str) -> std::path::PathBuf {
    let base = common::preset("paper-box-open.toml");
    let path = dir.join(name);
    let scene = if scene.is_empty() {
        String::new()
    } else {
        format!("[scene]\n{scene}\n")
    };
    std::fs::write(
        &path,
        format!("base = {base:?}\n\n{scene}\n[sweep]\n{sweep}\n"),
    )
    .unwrap();
    path
}

/// The quick scene: 5 mm elements, 4 mm of stroke, a 140 mm blank.
const QUICK: &str = "mesh.element_size = 5.0\nprocess.stroke = 4.0\nblank.size = 140.0";

#[test]
fn a_sweep_says_how_many_designs_and_how_long_and_starts_no_idle_workers() {
    let dir = tempfile::tempdir().unwrap();
    let file = sweep_file(dir.path(), "s.toml", QUICK, "r = [5.0, 10.0]");
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
    let one = sweep_file(dir.path(), "one.toml", QUICK, "r = [5.0]");
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
    let twice = sweep_file(dir.path(), "twice.toml", "", "r = [5.0, 5]");
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
    let file = sweep_file(
        dir.path(),
        "s.toml",
        "process.stroke = 4.0\nblank.size = 140.0",
        "r = [5.0]",
    );
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

#[test]
fn a_grown_grid_resumes_with_the_rows_of_the_same_values() {
    // A design is its values: adding r = 7.5 renumbers r = 10, whose row (and map and field)
    // is kept; only the new designs run.
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, r: &str| {
        sweep_file(
            dir.path(),
            name,
            QUICK,
            &format!("r = {r}\nfriction = [0.1, 0.2]"),
        )
    };
    let small = write("small.toml", "[5.0, 10.0]");
    let grown = write("grown.toml", "[5.0, 7.5, 10.0]");
    let o = wovenform(
        dir.path(),
        &["sweep", small.to_str().unwrap(), "--out", "o"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let before = std::fs::read_to_string(dir.path().join("o/results.csv")).unwrap();
    let o = wovenform(
        dir.path(),
        &["sweep", grown.to_str().unwrap(), "--out", "o", "--resume"],
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("kept 4 rows (2 renumbered"), "{err}");
    assert!(err.contains("2 designs to run"), "{err}");
    let after = std::fs::read_to_string(dir.path().join("o/results.csv")).unwrap();
    assert_eq!(after.lines().count(), 7, "{after}");
    // r = 10 at friction 0.1 was d002, now d004: same figures, its map and field renamed.
    let line = |text: &str, id: &str| {
        text.lines()
            .find(|l| l.contains(id))
            .map(|l| l.split(',').take(8).collect::<Vec<_>>().join(","))
    };
    let old_id = before
        .lines()
        .find(|l| l.starts_with("10,") && l.contains(",0.1,"))
        .and_then(|l| l.split(',').find(|f| f.starts_with("d00")))
        .unwrap()
        .to_string();
    let hash = old_id.split('-').nth(1).unwrap();
    let new_id = after
        .lines()
        .filter_map(|l| l.split(',').find(|f| f.ends_with(hash)))
        .next()
        .unwrap()
        .to_string();
    assert_ne!(old_id, new_id);
    assert_eq!(line(&before, &old_id), line(&after, &new_id));
    assert!(dir.path().join(format!("o/maps/{new_id}.png")).is_file());
    assert!(dir.path().join(format!("o/fields/{new_id}.json")).is_file());
    // The old files stay (a frontier's files, the explorer's table name them).
    assert!(dir.path().join(format!("o/fields/{old_id}.json")).is_file());
}
