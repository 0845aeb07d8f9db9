//! `wovenform converge` on a small ladder: the CSV has a row per rung with its error bounds,
//! the chart is written, no rung is reported with zero error, and ladders that cannot give a
//! reference are refused (the Richardson formula and the bounds are checked on known limits in
//! `src/study/converge.rs`).

use crate::common;

use common::{preset, text, wovenform_in};

#[test]
fn a_small_ladder_writes_its_table_and_chart() {
    let dir = tempfile::tempdir().unwrap();
    let out = wovenform_in(
        dir.path(),
        &[
            "converge",
            &preset("paper-box-open.toml"),
            "--out",
            "conv",
            "--sizes",
            "10,7.5,5",
            "--steps",
            "2,4,8",
            "--set",
            "process.stroke=8.0",
        ],
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}{}", stdout, text(&out.stderr));
    println!("{stdout}");
    let csv = std::fs::read_to_string(dir.path().join("conv/converge.csv")).unwrap();
    let rows: Vec<Vec<String>> = csv::Reader::from_reader(csv.as_bytes())
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 6, "{csv}");
    assert_eq!(rows.iter().filter(|r| r[0] == "mesh").count(), 3);
    assert!(
        rows.iter().all(|r| r[7] == "true"),
        "every rung converged: {csv}"
    );
    // Dofs grow as the mesh is refined.
    let dofs: Vec<usize> = rows[..3].iter().map(|r| r[3].parse().unwrap()).collect();
    assert!(dofs[0] < dofs[1] && dofs[1] < dofs[2], "{dofs:?}");
    // Every error is a finite bound, and none is zero: the finest rung is not its own exact
    // reference. A bound is at least the rung's distance to the finest rung minus the finest
    // rung's own bound (triangle inequality on |f − ref| + u).
    let err = |r: &Vec<String>, k: usize| r[12 + k].parse::<f64>().unwrap();
    assert!(
        rows.iter()
            .all(|r| (0..4).all(|k| err(r, k).is_finite() && err(r, k) > 0.0)),
        "{csv}"
    );
    let shear = |r: &Vec<String>| r[8].parse::<f64>().unwrap();
    for ladder in [&rows[..3], &rows[3..]] {
        let finest = ladder.last().unwrap();
        for r in ladder {
            let distance = (shear(r) - shear(finest)).abs();
            assert!(
                err(r, 0) + 1.5e-4 >= distance - err(finest, 0),
                "{r:?}\n{csv}"
            );
        }
    }
    // The punch force's error shrinks as the mesh is refined.
    assert!(
        err(&rows[0], 1) > err(&rows[1], 1) && err(&rows[1], 1) > err(&rows[2], 1),
        "{csv}"
    );
    assert!(stdout.contains("reference of the mesh ladder"), "{stdout}");
    assert!(
        stdout.contains("coarse (5 mm): max shear error ≤"),
        "{stdout}"
    );
    assert!(dir.path().join("conv/converge.png").exists());
}

#[test]
fn a_ladder_of_one_rung_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = wovenform_in(
        dir.path(),
        &[
            "converge",
            &preset("paper-box-open.toml"),
            "--out",
            "c",
            "--sizes",
            "5",
        ],
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("--sizes"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn ladders_in_the_wrong_order_or_with_repeats_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (option, value, must) in [
        ("--sizes", "6,10,12", "coarse to fine"),
        ("--sizes", "5,5,2.5", "coarse to fine"),
        ("--sizes", "5,2.5", "at least three rungs"),
        ("--steps", "8,4,2", "few to many"),
        ("--steps", "4,8", "at least three rungs"),
    ] {
        let out = wovenform_in(
            dir.path(),
            &[
                "converge",
                &preset("paper-box-open.toml"),
                "--out",
                "c",
                option,
                value,
            ],
        );
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{option} {value}: {err}");
        assert!(
            err.contains(option) && err.contains(must),
            "{option} {value}: {err}"
        );
    }
    assert!(!dir.path().join("c").exists(), "refused before any work");
}
