//! The command line as scripts use it: the real binary, its stdout, stderr and exit codes.

use crate::analytic;

use std::path::Path;
use std::process::{Command, Output};

use wovenform::core::fabric::law::{CellLaw, CellParams};

/// Runs the binary in a scratch folder of this test process, so that a command's default
/// output folder (`out/...`) lands there, not in the repository.
fn wovenform(args: &[&str]) -> Output {
    static SCRATCH: std::sync::OnceLock<tempfile::TempDir> = std::sync::OnceLock::new();
    let scratch = SCRATCH.get_or_init(|| tempfile::tempdir().expect("a scratch folder"));
    Command::new(env!("CARGO_BIN_EXE_wovenform"))
        .args(args)
        .current_dir(scratch.path())
        .output()
        .expect("the wovenform binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `law` and returns its JSON object.
fn law_json(args: &[&str]) -> serde_json::Map<String, serde_json::Value> {
    let o = wovenform(&[&["law"], args].concat());
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(&o));
    match serde_json::from_str(stdout(&o).trim()).expect("law prints one JSON object") {
        serde_json::Value::Object(m) => m,
        v => panic!("not an object: {v}"),
    }
}

fn assert_bad_input(args: &[&str], must_name: &[&str]) {
    let o = wovenform(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: stderr: {err}");
    for word in must_name {
        assert!(
            err.contains(word),
            "{args:?}: stderr does not name `{word}`: {err}"
        );
    }
}

#[test]
fn law_prints_the_reference_tension() {
    let m = law_json(&["--eps1", "0.004", "--eps2", "0.004"]);
    let mut keys: Vec<&str> = m.keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "closure", "dt11_de1", "dt11_de2", "dt22_de1", "dt22_de2", "t11", "t22", "w1", "w2"
        ]
    );
    let reference = analytic::LAW_REFERENCE[0];
    let num = |k: &str| m[k].as_f64().unwrap();
    let t11 = num("t11");
    assert!((t11 / reference.t[0] - 1.0).abs() < 1e-6, "t11 = {t11}");
    let closure = num("closure");
    assert!(
        (closure / reference.closure - 1.0).abs() < 1e-5,
        "closure = {closure}"
    );
    // The printed crown displacements and tensions satisfy the paper's equations (1)–(5).
    let p = CellParams::PAPER_GLASS;
    let (w, t) = ([num("w1"), num("w2")], [t11, num("t22")]);
    let res = analytic::paper_equation_residuals(&p, reference.eps, w, t);
    let force = 1e-9 * (t[0] + t[1]) + 1e-10 * (p.c[0] + p.c[1]);
    assert!(
        res[0].abs() <= force && res[2].abs() <= force && res[3].abs() <= force,
        "{res:?}"
    );
    assert!(res[1].abs() <= 1e-8 * p.a, "{res:?}");
}

#[test]
fn law_set_changes_the_result() {
    let base = law_json(&["--eps1", "0.004", "--eps2", "0.004"])["t11"]
        .as_f64()
        .unwrap();
    let m = law_json(&[
        "--eps1",
        "0.004",
        "--eps2",
        "0.004",
        "--set",
        "fabric.a=0.05",
    ]);
    let changed = m["t11"].as_f64().unwrap();
    assert!((changed - base).abs() > 1.0, "{base} vs {changed}");
    assert!((m["closure"].as_f64().unwrap() - 0.05).abs() < 0.01);
    // Arrays, and a scene file combined with --set.
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("fabric.toml");
    std::fs::write(&scene, "[fabric]\nl0 = 5.0\nc = 30000\n").unwrap();
    let s = scene.to_str().unwrap();
    let m = law_json(&[
        "--eps1",
        "0.01",
        "--eps2",
        "0",
        "--scene",
        s,
        "--set",
        "fabric.l0=[5.0,4.0]",
    ]);
    let law = CellLaw::new(CellParams {
        l0: [5.0, 4.0],
        c: [30000.0; 2],
        ..CellParams::PAPER_GLASS
    });
    let want = law.evaluate([0.01, 0.0], law.initial_state()).t[0];
    assert!((m["t11"].as_f64().unwrap() / want - 1.0).abs() < 1e-12);
}

#[test]
fn law_bad_input_exits_2_naming_the_key() {
    let eps = ["law", "--eps1", "0.004", "--eps2", "0.004"];
    fn with<'a>(eps: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [eps, extra].concat()
    }
    assert_bad_input(
        &with(&eps, &["--set", "fabric.foo=1"]),
        &["fabric.foo", "unknown key"],
    );
    assert_bad_input(
        &with(&eps, &["--set", "fabric.a=-1"]),
        &["fabric.a", "≥ 0 mm"],
    );
    assert_bad_input(&with(&eps, &["--set", "fabric.b=0"]), &["fabric.b", "> 0"]);
    assert_bad_input(
        &with(&eps, &["--set", "fabric.a=oops"]),
        &["fabric.a", "TOML literal"],
    );
    assert_bad_input(
        &with(&eps, &["--set", "fabric.l0=[5.0,4.0,3.0]"]),
        &["fabric.l0"],
    );
    assert_bad_input(&["law", "--eps1", "0.2", "--eps2", "0"], &["--eps1", "0.2"]);
    assert_bad_input(&["law", "--eps1", "0", "--eps2", "-0.06"], &["--eps2"]);

    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let bad_toml = file("bad.toml", "[fabric]\na = = 0.05\n");
    assert_bad_input(&with(&eps, &["--scene", &bad_toml]), &[&bad_toml, "line 2"]);
    let unknown = file("unknown.toml", "[fabric]\nl0 = 4.76\nthickness = 1\n");
    assert_bad_input(
        &with(&eps, &["--scene", &unknown]),
        &[&unknown, "fabric.thickness"],
    );
    let negative = file("negative.toml", "[fabric]\ne0 = -0.1\n");
    assert_bad_input(
        &with(&eps, &["--scene", &negative]),
        &[&negative, "fabric.e0"],
    );
    let missing = dir.path().join("missing.toml");
    let missing = missing.to_str().unwrap();
    assert_bad_input(&with(&eps, &["--scene", missing]), &[missing]);
}

#[test]
fn law_curves_write_the_figure6_csv_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fig");
    let o = wovenform(&["law", "--curves", "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(&o));
    let csv = out.join("figure6.csv");
    let png = out.join("figure6.png");
    assert!(stdout(&o).contains(csv.to_str().unwrap()));
    assert!(stdout(&o).contains(png.to_str().unwrap()));

    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("k,eps1,eps2,t11_n,t22_n"));
    let rows: Vec<Vec<f64>> = csv::Reader::from_reader(text.as_bytes())
        .records()
        .map(|r| {
            r.unwrap()
                .iter()
                .map(|f| f.parse::<f64>().unwrap())
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), 4 * 121);
    for (i, k) in [1.0, 2.0, 4.0, f64::INFINITY].into_iter().enumerate() {
        let curve = &rows[121 * i..121 * (i + 1)];
        assert!(curve.iter().all(|r| r[0] == k && r.len() == 5));
        assert_eq!(curve[0][1..], [0.0, 0.0, 0.0, 0.0]);
        assert!((curve[120][1] - 0.012).abs() < 1e-15);
        assert!(curve.iter().all(|r| (r[2] - r[1] / k).abs() < 1e-15));
        assert!(
            curve.windows(2).all(|w| w[1][3] > w[0][3]),
            "warp tension rises"
        );
    }
    // The reference point (0.004, 0.004) is row 40 of the k = 1 curve.
    let reference = analytic::LAW_REFERENCE[0];
    assert!(
        (rows[40][1] - reference.eps[0]).abs() < 1e-15,
        "{:?}",
        rows[40]
    );
    assert!(
        (rows[40][2] - reference.eps[1]).abs() < 1e-15,
        "{:?}",
        rows[40]
    );
    assert!((rows[40][3] / reference.t[0] - 1.0).abs() < 1e-6);

    assert_png(&png);
}

fn assert_png(path: &Path) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    let (w, h) = img.dimensions();
    assert!(
        (600..=3000).contains(&w) && (400..=3000).contains(&h),
        "{w}x{h}"
    );
    // Not blank: plenty of non-white pixels (axes, text, curves), but mostly white background.
    let inked = img.pixels().filter(|p| p.0 != [255, 255, 255]).count();
    let total = (w * h) as usize;
    assert!(
        inked > total / 100 && inked < total / 2,
        "{inked} of {total} pixels inked"
    );
}

/// Synthetic measurements from the law with A = 0.06 mm, B = 0.4 1/N on Figure 6's four strain
/// paths, with ±0.5 N of deterministic noise.
fn synthetic_csv() -> String {
    let law = CellLaw::new(CellParams {
        a: 0.06,
        b: 0.4,
        ..CellParams::PAPER_GLASS
    });
    let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
    let mut noise = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 1.0
    };
    let mut text = String::from("eps1,eps2,t11_n,t22_n\n");
    for k in [1.0, 2.0, 4.0, f64::INFINITY] {
        for i in 1..=50 {
            let e1 = 0.0002 * i as f64;
            let e2 = e1 / k;
            let t = law.evaluate([e1, e2], law.initial_state()).t;
            text.push_str(&format!(
                "{e1},{e2},{},{}\n",
                t[0] + noise(),
                t[1] + noise()
            ));
        }
    }
    text
}

/// The number after `NAME = ` on a line of the fit's output.
fn reported(out: &str, name: &str) -> f64 {
    let prefix = format!("{name} = ");
    let line = out
        .lines()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no `{prefix}` line in:\n{out}"));
    line[prefix.len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn fit_recovers_a_and_b_from_synthetic_curves() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("biaxial.csv");
    std::fs::write(&data, synthetic_csv()).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_wovenform"))
        .args(["fit", data.to_str().unwrap()])
        .current_dir(dir.path())
        .output()
        .expect("the wovenform binary runs");
    let out = stdout(&o);
    assert_eq!(
        o.status.code(),
        Some(0),
        "stdout: {out}\nstderr: {}",
        stderr(&o)
    );
    let (a, b) = (reported(&out, "A"), reported(&out, "B"));
    assert!((a / 0.06 - 1.0).abs() < 0.03, "A = {a}\n{out}");
    assert!((b / 0.4 - 1.0).abs() < 0.05, "B = {b}\n{out}");
    let rms = reported(&out, "RMS residual");
    assert!(
        rms > 0.1 && rms < 0.5,
        "RMS = {rms} (noise is uniform ±0.5 N, rms {:.2})",
        analytic::uniform_rms(0.5)
    );
    assert_eq!(reported(&out, "points"), 200.0);
    assert!(out.contains(" mm") && out.contains(" 1/N") && out.contains("C = 38000.0 N (fixed)"));
    // By default fit.png lands in a folder of its own (out/fit-<data stem>), not beside the data.
    assert_png(&dir.path().join("out/fit-biaxial/fit.png"));
    assert!(!dir.path().join("fit.png").exists());

    // With --fit-c and --out, C comes back too.
    let out_dir = dir.path().join("fitc");
    let o = wovenform(&[
        "fit",
        data.to_str().unwrap(),
        "--fit-c",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    let out = stdout(&o);
    assert_eq!(
        o.status.code(),
        Some(0),
        "stdout: {out}\nstderr: {}",
        stderr(&o)
    );
    let c = reported(&out, "C");
    assert!((c / 38000.0 - 1.0).abs() < 0.01, "C = {c}\n{out}");
    assert!((reported(&out, "A") / 0.06 - 1.0).abs() < 0.05, "{out}");
    assert_png(&out_dir.join("fit.png"));
}

#[test]
fn fit_reads_what_law_curves_writes() {
    // The law's own curves, written with A = 0.05 mm and B = 0.3 1/N over the paper's fabric,
    // fitted from the paper's values: the fit must come back to 0.05 and 0.3 (one naming of
    // the columns, t11_n and t22_n, on both sides).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("law");
    let o = wovenform(&[
        "law",
        "--curves",
        "--out",
        out.to_str().unwrap(),
        "--set",
        "fabric.a=0.05",
        "--set",
        "fabric.b=0.3",
    ]);
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(&o));
    let csv = out.join("figure6.csv");
    let fitted = out.join("fitted");
    let o = wovenform(&[
        "fit",
        csv.to_str().unwrap(),
        "--out",
        fitted.to_str().unwrap(),
    ]);
    let text = stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{text}\nstderr: {}", stderr(&o));
    assert!((reported(&text, "A") / 0.05 - 1.0).abs() < 1e-4, "{text}");
    assert!((reported(&text, "B") / 0.3 - 1.0).abs() < 1e-4, "{text}");
    assert!(reported(&text, "RMS residual") < 1e-3, "{text}");
}

#[test]
fn fit_bad_data_exits_2_naming_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let header = file("header.csv", "e1,e2,t11_n,t22_n\n0.001,0,1,1\n");
    assert_bad_input(&["fit", &header], &[&header, "line 1", "eps1"]);
    let number = file(
        "number.csv",
        "eps1,eps2,t11_n,t22_n\n0.001,0,1,1\n0.002,0,abc,1\n",
    );
    assert_bad_input(
        &["fit", &number],
        &[&number, "line 3", "column t11_n", "abc"],
    );
    let missing = dir.path().join("nothing.csv");
    let missing = missing.to_str().unwrap();
    assert_bad_input(&["fit", missing], &[missing]);
}

/// Writes `text` to `name` in `dir`; its path.
fn data_file(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn fit_refuses_data_without_information() {
    let dir = tempfile::tempdir().unwrap();
    let zero = data_file(
        dir.path(),
        "zero.csv",
        "eps1,eps2,t11_n,t22_n\n0.001,0.001,0,0\n0.002,0.001,0,0\n0.003,0.002,0,0\n",
    );
    assert_bad_input(&["fit", &zero], &[&zero, "every measured tension"]);
    let one = data_file(
        dir.path(),
        "one.csv",
        "eps1,eps2,t11_n,t22_n\n0.002,0.001,5,3\n0.002,0.001,5.2,3.1\n",
    );
    assert_bad_input(&["fit", &one], &[&one, "one strain"]);
    // Tensions scattered at random over random strains: no curve in them.
    let mut seed: u64 = 2;
    let mut uniform = |lo: f64, hi: f64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut text = String::from("eps1,eps2,t11_n,t22_n\n");
    for _ in 0..20 {
        let (e1, e2) = (uniform(-0.01, 0.01), uniform(-0.01, 0.01));
        let (t1, t2) = (uniform(-50.0, 50.0), uniform(-50.0, 50.0));
        text.push_str(&format!("{e1},{e2},{t1},{t2}\n"));
    }
    let scattered = data_file(dir.path(), "scattered.csv", &text);
    assert_bad_input(
        &["fit", &scattered],
        &[&scattered, "too little information", "not identified"],
    );
}

#[test]
fn fit_reports_a_parameter_the_data_do_not_pin() {
    // Linear tensions: a yarn stiffness, but no undulation for A to describe.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("eps1,eps2,t11_n,t22_n\n");
    for i in 1..=40 {
        let (e1, e2) = (0.0005 * i as f64, 0.0005 * (i % 7) as f64);
        let wiggle = if i % 2 == 0 { 1.0 } else { -1.0 };
        text.push_str(&format!(
            "{e1},{e2},{},{}\n",
            38000.0 * e1 + wiggle,
            38000.0 * e2 - wiggle
        ));
    }
    let linear = data_file(dir.path(), "linear.csv", &text);
    let o = wovenform(&["fit", &linear, "--fit-c"]);
    let (out, err) = (stdout(&o), stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}\n{err}");
    let a_line = out.lines().find(|l| l.starts_with("A = ")).unwrap();
    assert!(a_line.ends_with("on its bound)"), "{out}");
    assert!(
        err.contains(&format!("warning: {linear}: A = "))
            && err.contains("sits on its bound")
            && !err.contains("C = "),
        "{err}"
    );
    assert!(reported(&out, "C") > 0.0);
}

#[test]
fn fit_reads_a_file_with_a_byte_order_mark() {
    let dir = tempfile::tempdir().unwrap();
    let law = dir.path().join("law");
    let o = wovenform(&["law", "--curves", "--out", law.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let curves = std::fs::read_to_string(law.join("figure6.csv")).unwrap();
    let file = data_file(
        dir.path(),
        "bom.csv",
        &format!("\u{feff}# exported from a spreadsheet\n{curves}"),
    );
    let o = wovenform(&["fit", &file]);
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{out}\n{}", stderr(&o));
    assert!(reported(&out, "RMS residual") < 1e-3, "{out}");
}

#[test]
fn a_closed_pipe_ends_the_program_without_a_panic() {
    // `wovenform | head`: the reader is gone before the overview is printed.
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_wovenform"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .stdin(std::process::Stdio::null())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_ne!(out.status.code(), Some(101), "{err}");
}
