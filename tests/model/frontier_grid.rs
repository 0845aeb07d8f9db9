//! The frontier against a dense grid: the boundary in r of the paper's open box for two
//! (rp, rm) pairs at the coarse level, found by the root search on the 9-value axis, must hold
//! every place where a dense sweep of the same designs (r every 0.5 mm) crosses the locking
//! angle, with the side the range's ends give; and it must take at most a third of the
//! 9-value grid's runs.

use std::path::Path;

use wovenform::study::frontier::{self, Found, Lattice};
use wovenform::study::sweep::{self, Plan, Row};

use crate::common;

fn plan(dir: &Path, r_count: usize) -> Plan {
    let text = format!(
        "base = {:?}\n[sweep]\nr = {{ start = 4.0, stop = 20.0, count = {r_count} }}\nrp = [15.0]\nrm = [7.5, 10.0]\n",
        common::preset("paper-box-open.toml")
    );
    let path = dir.join(format!("frontier-{r_count}.toml"));
    std::fs::write(&path, text).unwrap();
    Plan::load(&path, &["mesh.element_size=5.0".into()]).unwrap()
}

/// Where the dense rows of one rm cross the locking angle (linear between neighbours), and
/// whether the shear is under it above each crossing.
fn dense_crossings(rows: &[Row], rm: f64, locking: f64) -> Vec<(f64, bool)> {
    let mut pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| {
            r.params
                .iter()
                .any(|(c, v)| c == "rm" && v.as_float() == Some(rm))
        })
        .map(|r| {
            let x = r
                .params
                .iter()
                .find(|(c, _)| c == "r")
                .unwrap()
                .1
                .as_float()
                .unwrap();
            (
                x,
                r.max_shear_deg.expect("every dense design answers") - locking,
            )
        })
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts.windows(2)
        .filter(|w| (w[0].1 > 0.0) != (w[1].1 > 0.0))
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            (a.0 + (b.0 - a.0) * a.1 / (a.1 - b.1), b.1 <= 0.0)
        })
        .collect()
}

#[test]
fn the_preset_frontier_takes_a_third_of_the_grids_runs_or_fewer() {
    // The paper's box over r 4–20 mm for the nine (rp, rm) pairs of the paper's sweep, coarse:
    // most pairs lock over the whole range (two runs tell), two have a boundary.
    let dir = tempfile::tempdir().unwrap();
    let file = common::preset("paper-box-frontier.toml");
    let plan = Plan::load(Path::new(&file), &["mesh.element_size=5.0".into()]).unwrap();
    let lattice = Lattice::new(&plan, "r").unwrap();
    let out = dir.path().join("f");
    let found = frontier::search(&lattice, &out, &frontier::Options::default(), &|_| {}).unwrap();
    assert_eq!(found.grid_runs(), 81);
    assert!(
        3 * found.runs() <= found.grid_runs(),
        "{} runs",
        found.runs()
    );
    let boundaries = found
        .lines
        .iter()
        .filter(|l| matches!(l.found, Found::Boundaries(_)));
    assert!(boundaries.count() >= 1);
    // Every run is a row of results.csv, and a resume runs none again.
    let text = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(text.lines().count(), 1 + found.runs());
    let options = frontier::Options {
        resume: true,
        ..Default::default()
    };
    let again = frontier::search(&lattice, &out, &options, &|_| {}).unwrap();
    assert_eq!((again.ran, again.kept), (0, found.runs()));
    assert_eq!(again.lines, found.lines);
}

#[test]
fn the_frontier_in_r_holds_the_dense_grids_crossings_in_a_third_of_the_runs() {
    let dir = tempfile::tempdir().unwrap();
    let coarse = plan(dir.path(), 9);
    let lattice = Lattice::new(&coarse, "r").unwrap();
    let found = frontier::search(
        &lattice,
        &dir.path().join("frontier"),
        &frontier::Options::default(),
        &|_| {},
    )
    .unwrap();
    assert_eq!(found.lines.len(), 2);
    // Both pairs have a boundary in range: the grid's 9 runs each against a few.
    assert!(
        2 * found.runs() <= found.grid_runs(),
        "{} runs against the grid's {}",
        found.runs(),
        found.grid_runs()
    );
    let dense_plan = plan(dir.path(), 33);
    let dense = sweep::run(
        &dense_plan,
        &dir.path().join("dense"),
        &sweep::Options::default(),
        &|_| {},
    )
    .unwrap();
    let locking = coarse.base_scene.fabric.locking_angle_deg;
    let mut crossings_seen = 0;
    for line in &found.lines {
        let rm = line.values[0].2.as_float().unwrap();
        let crossings = dense_crossings(&dense.rows, rm, locking);
        crossings_seen += crossings.len();
        match &line.found {
            Found::Boundaries(bs) => {
                // Every crossing (a wiggle of the figure inside its band crosses more than
                // once) lies in an interval; the side is the one from the range's ends.
                for (x, _) in &crossings {
                    let holds = bs
                        .iter()
                        .any(|b| b.interval[0] <= *x && *x <= b.interval[1]);
                    assert!(
                        holds,
                        "rm {rm}: the dense grid crosses at r = {x:.2}: {bs:?}"
                    );
                }
                let net_up = crossings.iter().filter(|c| c.1).count() > crossings.len() / 2;
                assert!(
                    bs.iter().all(|b| b.feasible_above == net_up),
                    "rm {rm}: {bs:?}"
                );
            }
            other => assert!(crossings.is_empty(), "rm {rm}: {other:?} but {crossings:?}"),
        }
    }
    assert!(
        crossings_seen > 0,
        "the pairs were chosen for a boundary in range"
    );
}
