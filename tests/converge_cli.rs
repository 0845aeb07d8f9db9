//! `wovenform converge` on a small ladder: the CSV has a row per rung with its errors, the
//! chart is written, and the errors shrink towards the reference (the reference being the
//! finest rung or a Richardson extrapolation, whose formula is checked on a known limit in
//! `src/study/converge.rs`).

mod common;

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
            "2,4",
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
    assert_eq!(rows.len(), 5, "{csv}");
    assert_eq!(rows.iter().filter(|r| r[0] == "mesh").count(), 3);
    assert!(
        rows.iter().all(|r| r[7] == "true"),
        "every rung converged: {csv}"
    );
    // Dofs grow as the mesh is refined.
    let dofs: Vec<usize> = rows[..3].iter().map(|r| r[3].parse().unwrap()).collect();
    assert!(dofs[0] < dofs[1] && dofs[1] < dofs[2], "{dofs:?}");
    // Every error is a finite number. The max shear's reference is the finest rung of each
    // ladder (README, "Error against run time"): its error is the distance to that rung's
    // shear, to the printed precision (4 decimals).
    let err = |r: &Vec<String>, k: usize| r[12 + k].parse::<f64>().unwrap();
    assert!(
        rows.iter().all(|r| (0..4).all(|k| err(r, k).is_finite())),
        "{csv}"
    );
    let shear = |r: &Vec<String>| r[8].parse::<f64>().unwrap();
    for ladder in [&rows[..3], &rows[3..]] {
        let finest = shear(ladder.last().unwrap());
        for r in ladder {
            let distance = (shear(r) - finest).abs();
            assert!((err(r, 0) - distance).abs() < 1.5e-4, "{r:?}\n{csv}");
        }
    }
    // The punch force's error shrinks as the mesh is refined.
    assert!(
        err(&rows[0], 1) > err(&rows[1], 1) && err(&rows[1], 1) > err(&rows[2], 1),
        "{csv}"
    );
    assert!(stdout.contains("reference of the mesh ladder"), "{stdout}");
    assert!(
        stdout.contains("coarse (5 mm): max shear error"),
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
