//! `wovenform slurm`: the job array and the merge job it writes, run here task by task as
//! Slurm would run them (one task killed mid-run and run again, as a requeue does), give the
//! rows of a local sweep of the same file, each design once; `--submit` passes the array's
//! job id to the merge's dependency; a merge run again (after a partial one) finishes what is
//! missing; an output folder of another sweep is refused up front; the options are checked as
//! Slurm takes them. (A real single-node Slurm: `tests/slurm_cluster.rs`.)

use crate::slurm_common;
use slurm_common::rows;

use std::path::Path;
use std::process::Command;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_wovenform")
}

fn sweep_file() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/paper-box-explorer.toml")
}

#[test]
fn the_array_and_a_repeated_merge_give_the_local_sweep_each_design_once() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cluster");
    let st = Command::new(bin())
        .arg("slurm")
        .arg(sweep_file())
        .args([
            "--out",
            out.to_str().unwrap(),
            "--tasks",
            "3",
            "--min-task-s",
            "0",
        ])
        .args(["--accuracy", "coarse", "--time", "00:10:00"])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let scripts = out.join("slurm");
    let array = std::fs::read_to_string(scripts.join("array.sh")).unwrap();
    assert!(array.contains("#SBATCH --array=1-3"), "{array}");
    let task = |i: usize| {
        let mut c = Command::new("bash");
        c.arg(scripts.join("array.sh"))
            .env("SLURM_ARRAY_TASK_ID", i.to_string())
            .env("SLURM_CPUS_PER_TASK", "1");
        c
    };
    // Task 2 is killed early (preempted), then runs again (requeued).
    let mut child = task(2).spawn().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(700));
    child.kill().unwrap();
    let _ = child.wait();
    for i in [1, 2, 3] {
        let o = task(i).output().unwrap();
        assert!(
            o.status.success(),
            "task {i}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let merge = || {
        let o = Command::new("bash")
            .arg(scripts.join("merge.sh"))
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "merge: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    // Task 3 had not finished its last design when the merge was run by hand: the merge
    // takes the 7 designs there are.
    let shard3 = out.join("shards/3/results.csv");
    let csv = std::fs::read_to_string(&shard3).unwrap();
    let cut = csv.trim_end().rfind('\n').unwrap() + 1;
    std::fs::write(&shard3, &csv[..cut]).unwrap();
    merge();
    assert_eq!(rows(&out).0, 7);
    // Task 3 finishes; the merge runs again, and once more: each design once.
    let o = task(3).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    merge();
    let first = rows(&out);
    merge();
    assert_eq!(rows(&out), first, "the merge run again changes nothing");
    let local = tmp.path().join("local");
    let o = Command::new(bin())
        .arg("sweep")
        .arg(sweep_file())
        .args(["--out", local.to_str().unwrap(), "--accuracy", "coarse"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (n_cluster, cluster) = rows(&out);
    let (n_local, local) = rows(&local);
    assert_eq!(n_local, 8);
    assert_eq!(n_cluster, 8, "each design once");
    assert_eq!(cluster, local);
}

#[test]
fn submit_passes_the_array_id_to_the_merge() {
    let tmp = tempfile::tempdir().unwrap();
    let fake = tmp.path().join("bin");
    std::fs::create_dir_all(&fake).unwrap();
    let log = tmp.path().join("sbatch.log");
    // A stand-in sbatch: records its arguments, answers job ids as --parsable does.
    let script = format!(
        "#!/bin/bash\necho \"$@\" >> '{}'\nn=$(wc -l < '{}')\necho \"$((4000 + n));cluster\"\n",
        log.display(),
        log.display()
    );
    let sbatch = fake.join("sbatch");
    std::fs::write(&sbatch, script).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&sbatch, std::fs::Permissions::from_mode(0o755)).unwrap();
    let path = format!(
        "{}:{}",
        fake.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = tmp.path().join("cluster");
    let o = Command::new(bin())
        .arg("slurm")
        .arg(sweep_file())
        .args(["--out", out.to_str().unwrap(), "--tasks", "2", "--submit"])
        .args(["--partition", "short"])
        .env("PATH", path)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("array job 4001, merge job 4002"),
        "{stdout}"
    );
    let calls = std::fs::read_to_string(&log).unwrap();
    let lines: Vec<&str> = calls.lines().collect();
    assert_eq!(lines.len(), 2, "{calls}");
    assert!(lines[0].contains("array.sh"), "{calls}");
    assert!(
        lines[1].contains("--dependency=afterok:4001") && lines[1].contains("merge.sh"),
        "{calls}"
    );
    // Bad options are refused before anything is written.
    for bad in [["--time", "90 minutes"], ["--partition", "a b"]] {
        let o = Command::new(bin())
            .arg("slurm")
            .arg(sweep_file())
            .args([
                "--out",
                tmp.path().join("x").to_str().unwrap(),
                "--tasks",
                "2",
            ])
            .args(bad)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
        assert!(String::from_utf8_lossy(&o.stderr).contains(bad[0]));
    }
}

fn slurm(args: &[&str], out: &Path) -> std::process::Output {
    Command::new(bin())
        .arg("slurm")
        .arg(sweep_file())
        .arg("--out")
        .arg(out)
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// A sweep folder of the explorer's sweep with no design run (shard 9/9 of its 8 designs is
/// empty): its lock and an empty results.csv. `set`: a base scene override.
fn empty_sweep(dir: &Path, set: &[&str]) {
    let mut c = Command::new(bin());
    c.arg("sweep").arg(sweep_file()).arg("--out").arg(dir);
    for s in set {
        c.args(["--set", s]);
    }
    let o = c
        .args(["--shard", "9/9", "--accuracy", "coarse"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn an_output_folder_of_another_sweep_is_refused_up_front_and_by_the_merge() {
    let tmp = tempfile::tempdir().unwrap();
    let other = tmp.path().join("other");
    empty_sweep(&other, &["process.stroke=20.0"]);
    let before = std::fs::read(other.join("results.csv")).unwrap();
    let args = ["--tasks", "2", "--accuracy", "coarse"];
    // --out holds another sweep, or one of its shard folders does.
    let o = slurm(&args, &other);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(&other.display().to_string())
            && stderr(&o).contains("holds another sweep"),
        "{}",
        stderr(&o)
    );
    assert!(!other.join("slurm").exists(), "nothing written");
    let out = tmp.path().join("cluster");
    empty_sweep(&out.join("shards/2"), &["process.stroke=20.0"]);
    let o = slurm(&args, &out);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("shards/2") && stderr(&o).contains("holds another sweep"));
    assert!(!out.join("slurm").exists(), "nothing written");
    // A folder of this very sweep is taken (a run again, after a partial merge).
    let same = tmp.path().join("same");
    empty_sweep(&same, &[]);
    let o = slurm(&args, &same);
    assert!(o.status.success(), "{}", stderr(&o));
    // The merge into a folder of another sweep, or into rows of no known sweep: refused,
    // the folder as it was.
    let shard = tmp.path().join("shard");
    empty_sweep(&shard, &[]);
    let merge = |into: &Path| {
        Command::new(bin())
            .arg("merge")
            .arg(&shard)
            .arg("--out")
            .arg(into)
            .output()
            .unwrap()
    };
    let o = merge(&other);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("holds another sweep"), "{}", stderr(&o));
    assert_eq!(std::fs::read(other.join("results.csv")).unwrap(), before);
    let loose = tmp.path().join("loose");
    std::fs::create_dir_all(&loose).unwrap();
    std::fs::write(loose.join("results.csv"), "mine\n").unwrap();
    let o = merge(&loose);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("loose/results.csv, which wovenform did not write"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read_to_string(loose.join("results.csv")).unwrap(),
        "mine\n"
    );
}

/// `args` with `--tasks 2` unless they give --tasks.
fn with_tasks<'a>(args: &[&'a str]) -> Vec<&'a str> {
    let mut all = args.to_vec();
    if !args.iter().any(|a| a.starts_with("--tasks")) {
        all.extend(["--tasks", "2"]);
    }
    all
}

#[test]
fn slurm_options_are_checked_as_slurm_takes_them() {
    let tmp = tempfile::tempdir().unwrap();
    // Every form of sbatch --time, and the largest counts: written as given.
    for (i, (option, value)) in [
        ("--time", "1440"),
        ("--time", "100000"),
        ("--time", "UNLIMITED"),
        ("--time", "infinite"),
        ("--time", "90:30"),
        ("--time", "2-12"),
        ("--time", "2-12:30"),
        ("--time", "10-00:00:00"),
        ("--cpus-per-task", "4096"),
        ("--tasks", "4000000"),
    ]
    .into_iter()
    .enumerate()
    {
        let out = tmp.path().join(format!("ok{i}"));
        let o = slurm(&with_tasks(&[option, value]), &out);
        assert!(o.status.success(), "{option} {value}: {}", stderr(&o));
        let array = std::fs::read_to_string(out.join("slurm/array.sh")).unwrap();
        if option != "--tasks" {
            assert!(
                array.contains(&format!("#SBATCH {option}={value}\n")),
                "{array}"
            );
        }
    }
    // Nonsense: refused before anything is written.
    for (i, (option, value)) in [
        ("--time", "1h"),
        ("--time", "-1"),
        ("--time", "01;rm"),
        ("--time", "1-"),
        ("--time", "1:2:3:4"),
        ("--time", "forever"),
        ("--time", "99999999999"),
        ("--tasks", "0"),
        ("--tasks", "4000001"),
        ("--tasks", "1000000000"),
        ("--cpus-per-task", "0"),
        ("--cpus-per-task", "4097"),
        ("--cpus-per-task", "1000000000"),
        ("--cpus-per-task", "1e9"),
        ("--min-task-s", "inf"),
        ("--min-task-s", "NaN"),
        ("--min-task-s", "-1"),
        ("--partition", "a b"),
        ("--partition", "a\nb"),
    ]
    .into_iter()
    .enumerate()
    {
        let out = tmp.path().join(format!("bad{i}"));
        let o = slurm(&with_tasks(&[&format!("{option}={value}")]), &out);
        assert_eq!(o.status.code(), Some(2), "{option} {value}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(option),
            "{option} {value}: {}",
            stderr(&o)
        );
        assert!(
            !out.exists(),
            "{option} {value}: written before the refusal"
        );
    }
}
