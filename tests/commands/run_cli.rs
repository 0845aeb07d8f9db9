//! `wovenform run` as scripts use it: the real binary on the presets, coarse and short (a
//! 5 mm mesh, a few mm of stroke) so that each run takes well under a second.

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::{Map, Value};

use crate::analytic;
use crate::common;
use common::{preset, text, wovenform_in};

/// Coarse and short: the open box at 5 mm elements and 4 mm of stroke.
/// A coarse, shallow run on a 140 mm blank (the sizes below are counted from it).
const QUICK: [&str; 6] = [
    "--set",
    "mesh.element_size=5",
    "--set",
    "process.stroke=4",
    "--set",
    "blank.size=140",
];

fn run_json(dir: &Path, extra: &[&str]) -> (Output, Map<String, Value>) {
    let open = preset("paper-box-open.toml");
    let args = [&["run", open.as_str(), "--json"], &QUICK[..], extra].concat();
    let o = wovenform_in(dir, &args);
    let out = text(&o.stdout);
    let v: Value = serde_json::from_str(out.trim())
        .unwrap_or_else(|e| panic!("stdout is not one JSON object ({e}): {out}"));
    match v {
        Value::Object(m) => (o, m),
        v => panic!("not an object: {v}"),
    }
}

const REQUIRED: [&str; 15] = [
    "scene",
    "converged",
    "failure",
    "max_shear_deg",
    "max_shear_at",
    "area_over_limit_pct",
    "max_tension_n",
    "punch_force_n",
    "feasible",
    "locking_angle_deg",
    "wall_s",
    "dofs",
    "steps",
    "newton_iterations",
    "left_out",
];

const EXTRAS: [&str; 7] = [
    "stroke_reached_mm",
    "penetration_mm",
    "draw_in_mm",
    "break_tension_n",
    "stabilisation_work_share",
    "unsound",
    "cutbacks",
];

fn num(m: &Map<String, Value>, k: &str) -> f64 {
    m[k].as_f64()
        .unwrap_or_else(|| panic!("{k} is not a number: {}", m[k]))
}

/// Pixels of an RGB image whose colour is `c` (exactly), counted left and right of column `x`.
fn count_colour(img: &image::RgbImage, c: [u8; 3], x: u32) -> (usize, usize) {
    let (mut left, mut right) = (0, 0);
    for (px, _, p) in img.enumerate_pixels() {
        if p.0 == c {
            if px < x {
                left += 1;
            } else {
                right += 1;
            }
        }
    }
    (left, right)
}

/// The magenta of the cells over the limit (`report::maps::OVER_LIMIT`), written out here.
const MAGENTA: [u8; 3] = [230, 0, 150];
/// Where the map ends and the colour bar begins (1100 px wide image, 250 px bar).
const BAR_X: u32 = 850;

/// A minimal VTU reader: the piece's counts and each named DataArray's numbers.
struct Vtu {
    points: usize,
    cells: usize,
    arrays: Vec<(String, usize, Vec<f64>)>,
}

fn read_vtu(path: &Path) -> Vtu {
    let s = std::fs::read_to_string(path).unwrap();
    assert!(s.starts_with("<?xml"), "not XML");
    assert!(s.contains("<VTKFile type=\"UnstructuredGrid\""));
    let attr = |tag: &str, name: &str| -> String {
        let at = tag.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
        tag[at..].split('"').next().unwrap().to_string()
    };
    let piece = &s[s.find("<Piece ").unwrap()..];
    let piece = &piece[..piece.find('>').unwrap()];
    let points = attr(piece, "NumberOfPoints").parse().unwrap();
    let cells = attr(piece, "NumberOfCells").parse().unwrap();
    let mut arrays = Vec::new();
    let mut rest = s.as_str();
    while let Some(start) = rest.find("<DataArray ") {
        rest = &rest[start..];
        let head_end = rest.find('>').unwrap();
        let head = &rest[..head_end];
        let body_end = rest.find("</DataArray>").unwrap();
        let values = rest[head_end + 1..body_end]
            .split_whitespace()
            .map(|t| t.parse::<f64>().unwrap())
            .collect();
        let components = attr(head, "NumberOfComponents").parse().unwrap();
        arrays.push((attr(head, "Name"), components, values));
        rest = &rest[body_end..];
    }
    Vtu {
        points,
        cells,
        arrays,
    }
}

impl Vtu {
    fn array(&self, name: &str) -> (usize, &[f64]) {
        let a = self
            .arrays
            .iter()
            .find(|a| a.0 == name)
            .unwrap_or_else(|| panic!("no array {name}"));
        (a.1, &a.2)
    }
}

#[test]
fn run_json_prints_the_fields_and_writes_the_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("box");
    let (o, m) = run_json(dir.path(), &["--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "stderr: {}", text(&o.stderr));
    for k in REQUIRED.iter().chain(&EXTRAS) {
        assert!(m.contains_key(*k), "missing {k}: {m:?}");
    }
    assert_eq!(m["scene"], "paper-box-open");
    assert_eq!(m["converged"], true);
    assert!(m["failure"].is_null());
    let (shear, limit) = (num(&m, "max_shear_deg"), num(&m, "locking_angle_deg"));
    let (tension, breaking) = (num(&m, "max_tension_n"), num(&m, "break_tension_n"));
    assert_eq!(limit, 60.0);
    let word = analytic::verdict_word(
        (shear, num(&m, "max_shear_err_deg"), limit),
        (tension, num(&m, "max_tension_err_pct"), breaking),
    );
    assert_eq!(m["feasible"].as_bool().unwrap(), word == "FEASIBLE");
    assert!(m["verdict"].as_str().unwrap().starts_with(word), "{m:?}");
    assert!(shear > 0.0 && shear < limit, "shear {shear}");
    assert!(num(&m, "punch_force_n") > 0.0);
    assert!((num(&m, "stroke_reached_mm") - 4.0).abs() < 1e-9);
    assert_eq!(m["max_shear_at"].as_array().unwrap().len(), 3);
    assert!(m["dofs"].as_u64().unwrap() > 0);
    assert!(m["steps"].as_u64().unwrap() > 0);
    assert!(m["newton_iterations"].as_u64().unwrap() >= m["steps"].as_u64().unwrap());
    assert!(
        m["left_out"]
            .as_array()
            .unwrap()
            .iter()
            .any(|s| s.as_str().unwrap().contains("undulation")),
        "the box preset runs the linear yarn law: {}",
        m["left_out"]
    );

    // summary.json holds the same object.
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary, Value::Object(m.clone()));

    // The maps decode; the magenta of "over the limit" is only on the shear map's colour bar.
    // The tension, a fraction of the break, is drawn on its own range (the break named above
    // the bar), so its largest values are drawn dark, not pale.
    for name in ["shear.png", "tension.png"] {
        let img = image::open(out.join(name)).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (1100, 900), "{name}");
        let (map, bar) = count_colour(&img, MAGENTA, BAR_X);
        assert_eq!(map, 0, "{name}: magenta cells on a feasible map");
        if name == "shear.png" {
            assert!(bar > 100, "{name}: no over-the-limit swatch on the bar");
        } else {
            assert_eq!(
                bar, 0,
                "{name}: an over-the-limit swatch for a field under it"
            );
            let dark = img
                .enumerate_pixels()
                .filter(|(x, _, p)| *x < BAR_X && p.0[0] < 60 && p.0[2] > 120)
                .count();
            assert!(dark > 50, "{name}: {dark} dark pixels on the map");
        }
        let inked = img.pixels().filter(|p| p.0 != [255, 255, 255]).count();
        assert!(inked > 100_000, "{name}: {inked} inked pixels");
    }

    // The VTU: the full blank (the quarter mirrored), every array present and of the right
    // length. The quarter is 70 mm / 5 mm = 14 elements a side: the full blank 28 × 28.
    let vtu = read_vtu(&out.join("result.vtu"));
    assert_eq!(vtu.cells, 28 * 28);
    assert_eq!(vtu.points, 29 * 29);
    for (name, per_cell) in [
        ("shear_deg", true),
        ("t11_n", true),
        ("t22_n", true),
        ("tension_max_n", true),
        ("contact", false),
        ("displacement", false),
        ("points", false),
    ] {
        let (c, v) = vtu.array(name);
        let n = if per_cell { vtu.cells } else { vtu.points };
        assert_eq!(v.len(), c * n, "{name}");
    }
    let (_, conn) = vtu.array("connectivity");
    assert_eq!(conn.len(), 4 * vtu.cells);
    assert!(conn.iter().all(|&i| i >= 0.0 && (i as usize) < vtu.points));
    let (_, types) = vtu.array("types");
    assert!(types.iter().all(|&t| t == 9.0), "VTK_QUAD");
    let (_, contact) = vtu.array("contact");
    assert!(contact.iter().all(|&c| [0.0, 1.0, 2.0, 3.0].contains(&c)));
    assert!(contact.contains(&1.0), "no node on the punch");
    // The figures agree with the JSON, and the mirror images cancel the signed shear.
    let (_, s) = vtu.array("shear_deg");
    let max_abs = s.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!((max_abs - shear).abs() < 1e-9 * shear.max(1.0));
    assert!(s.iter().sum::<f64>().abs() < 1e-9 * s.len() as f64 * shear);
    let (_, t) = vtu.array("tension_max_n");
    assert!((t.iter().cloned().fold(0.0, f64::max) - tension).abs() < 1e-9 * tension);
    // The deformed blank is symmetric about x = 0 and y = 0.
    let (_, p) = vtu.array("points");
    for axis in 0..2 {
        let lo = p.chunks(3).map(|q| q[axis]).fold(f64::INFINITY, f64::min);
        let hi = p
            .chunks(3)
            .map(|q| q[axis])
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(
            (lo + hi).abs() < 1e-9 && hi > 60.0,
            "axis {axis}: {lo}..{hi}"
        );
    }
}

#[test]
fn over_the_limit_is_a_result_drawn_in_magenta() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("low-limit");
    let (o, m) = run_json(
        dir.path(),
        &[
            "--set",
            "fabric.locking_angle_deg=1",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "infeasible is not an error: {}",
        text(&o.stderr)
    );
    assert_eq!(m["converged"], true);
    assert_eq!(m["feasible"], false);
    assert!(num(&m, "max_shear_deg") > 1.0);
    let pct = num(&m, "area_over_limit_pct");
    assert!(pct > 0.0 && pct < 100.0, "{pct}");
    assert!(m["verdict"].as_str().unwrap().contains("locking angle"));
    let img = image::open(out.join("shear.png")).unwrap().to_rgb8();
    let (map, _) = count_colour(&img, MAGENTA, BAR_X);
    assert!(map > 500, "only {map} magenta pixels on the map");
}

#[test]
fn run_text_names_units_and_files_in_the_default_folder() {
    let dir = tempfile::tempdir().unwrap();
    let hemi = preset("hemisphere.toml");
    let args = [
        &["run", hemi.as_str()][..],
        &QUICK[..],
        &["--set", "fabric.undulation=false"],
    ]
    .concat();
    let o = wovenform_in(dir.path(), &args);
    let out = text(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{out}\n{}", text(&o.stderr));
    for word in [
        "verdict",
        "max shear",
        "°",
        " N",
        " mm",
        "MPa",
        "hemisphere",
    ] {
        assert!(out.contains(word), "no `{word}` in:\n{out}");
    }
    let folder: PathBuf = ["out", "hemisphere"].iter().collect();
    for name in [
        "summary.json",
        "shear.png",
        "tension.png",
        "shear_developed.png",
        "tension_developed.png",
        "form.png",
        "result.vtu",
    ] {
        let path = folder.join(name);
        assert!(out.contains(path.to_str().unwrap()), "{name} not printed");
        assert!(dir.path().join(&path).is_file(), "{name} not written");
    }
    // Nothing drawn on stderr when it is not a terminal (no progress bar).
    assert!(o.stderr.is_empty(), "stderr: {}", text(&o.stderr));
}

#[test]
fn exit_code_follows_the_outcome() {
    // 0 for a converged, sound run, 1 for a run without an answer or with one that cannot be
    // trusted; the files are written in every case, showing where it stopped.
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    // Without the stabilisation the slack fabric is a mechanism: the run still converges (on a
    // shifted tangent) and says it met one. Whether a given iteration meets it depends on
    // Newton's path, so five short strokes are run: each converges and exits 0, and at least
    // one says it met a mechanism (on 2026-12-07: the strokes of 4, 5 and 6 mm).
    let mut met = Vec::new();
    for stroke in [2, 3, 4, 5, 6] {
        let (o, m) = run_json(
            dir.path(),
            &[
                "--set",
                "numerics.stabilisation=0",
                "--set",
                &format!("process.stroke={stroke}"),
                "--out",
                &out(&format!("free{stroke}")),
            ],
        );
        assert_eq!(o.status.code(), Some(0), "{m:?}\n{}", text(&o.stderr));
        assert_eq!(m["converged"], true);
        assert!(m["failure"].is_null());
        if m["mechanism"] == true {
            met.push(stroke);
        }
    }
    assert!(!met.is_empty(), "no stroke met a mechanism");
    // No friction: nothing holds the flange back, no unique shape, no answer.
    let (o, m) = run_json(
        dir.path(),
        &["--set", "process.friction=0", "--out", &out("loose")],
    );
    assert_eq!(o.status.code(), Some(1), "{m:?}");
    assert_eq!(m["converged"], false);
    assert_eq!(m["feasible"], false);
    assert!(m["failure"].as_str().unwrap().contains("no unique shape"));
    assert!(
        text(&o.stderr).contains("has no answer"),
        "{}",
        text(&o.stderr)
    );
    // A penalty factor of 1e-3 (the default is 10): converged, but the blank sinks into the
    // tools.
    let (o, m) = run_json(
        dir.path(),
        &[
            "--set",
            "numerics.penalty_factor=1e-3",
            "--out",
            &out("soft"),
        ],
    );
    assert_eq!(o.status.code(), Some(1), "{m:?}");
    assert_eq!(m["converged"], true);
    assert_eq!(m["feasible"], false);
    assert!(!m["unsound"].as_array().unwrap().is_empty(), "{m:?}");
    assert!(
        text(&o.stderr).contains("cannot be trusted"),
        "{}",
        text(&o.stderr)
    );
    for name in ["free2", "free6", "loose", "soft"] {
        assert!(dir.path().join(name).join("shear.png").is_file(), "{name}");
    }
}

#[test]
fn an_accuracy_level_sets_the_mesh_and_reports_its_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = common::wovenform_in(
        dir.path(),
        &[
            "run",
            &common::preset("paper-box-open.toml"),
            "--accuracy",
            "coarse",
            "--set",
            "process.stroke=6.0",
            "--json",
            "--out",
            "o",
        ],
    );
    assert!(out.status.success(), "{}", common::text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["accuracy"], "coarse");
    let level = wovenform::accuracy::Accuracy::Coarse.error();
    assert_eq!(v["max_shear_err_deg"], level.max_shear_deg);
    assert_eq!(v["punch_force_err_pct"], level.punch_force_pct);
    assert_eq!(v["inputs"]["mesh"]["element_size"], 5.0);
    assert!(v["wall_s"].as_f64().unwrap() > 0.0);
    let bad = common::wovenform_in(
        dir.path(),
        &[
            "run",
            &common::preset("paper-box-open.toml"),
            "--accuracy",
            "medium",
        ],
    );
    assert_eq!(bad.status.code(), Some(2));
    assert!(common::text(&bad.stderr).contains("coarse, standard or fine"));
}

#[test]
fn an_unusable_output_is_refused_before_solving() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("taken"), "a file").unwrap();
    let out = wovenform_in(
        dir.path(),
        &["run", &preset("paper-box-tight.toml"), "--out", "taken"],
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains("taken") && err.contains("output folder"),
        "{err}"
    );
    // Refused before the solve: no summary was printed.
    assert!(out.stdout.is_empty(), "{}", text(&out.stdout));
}

#[test]
fn the_inputs_of_a_summary_run_back_as_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, extra) in [
        ("paper-box-open.toml", &QUICK[..]),
        (
            "hemisphere.toml",
            &["--set", "mesh.element_size=5", "--set", "process.stroke=4"][..],
        ),
    ] {
        let first = wovenform_in(
            dir.path(),
            &[&["run", &preset(scene), "--json", "--out", "a"], extra].concat(),
        );
        assert!(first.status.success(), "{}", text(&first.stderr));
        let m: Value = serde_json::from_slice(&first.stdout).unwrap();
        // The inputs hold only the keys of their kind of punch.
        let tools = m["inputs"]["tools"].as_object().unwrap();
        let box_keys = ["side", "r", "rp"].iter().any(|k| tools.contains_key(*k));
        assert_eq!(box_keys, scene.starts_with("paper-box"), "{tools:?}");
        assert_eq!(tools.contains_key("radius"), scene == "hemisphere.toml");
        assert!(!tools.contains_key("axes"), "{tools:?}");
        // Written as TOML, they are a scene that runs to the same figures.
        let toml_text = toml::to_string(&m["inputs"]).unwrap();
        std::fs::write(dir.path().join("again.toml"), toml_text).unwrap();
        let again = wovenform_in(dir.path(), &["run", "again.toml", "--json", "--out", "b"]);
        assert!(again.status.success(), "{}", text(&again.stderr));
        let n: Value = serde_json::from_slice(&again.stdout).unwrap();
        for k in ["max_shear_deg", "max_tension_n", "punch_force_n"] {
            assert_eq!(m[k], n[k], "{scene}: {k}");
        }
    }
}
