//! The sweep on a real Slurm: a single-node cluster — Debian's slurm-wlm, the
//! controller and the node daemon on this machine, munge for authentication, a minimal
//! configuration written here — runs `wovenform slurm --submit`'s job array of three tasks and
//! the merge that depends on it. One array task is requeued while it runs (`scontrol
//! requeue`, as a preemption does): the merged `results.csv` must hold every design once, with
//! the figures of a local `sweep` of the same file. Every daemon started is stopped.
//!
//! Ignored by `cargo test` (it needs slurm-wlm and root); `.ci/run` installs them and runs it
//! with `cargo test --release --test slurm_cluster -- --ignored`.

mod slurm_common;
use slurm_common::rows;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_wovenform")
}

fn run(cmd: &str, args: &[&str], conf: &Path) -> Output {
    Command::new(cmd)
        .args(args)
        .env("SLURM_CONF", conf)
        .output()
        .unwrap_or_else(|e| panic!("{cmd}: {e} (is slurm-wlm installed?)"))
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// The cluster's daemons, stopped when dropped.
struct Cluster {
    conf: PathBuf,
    munged: Option<u32>,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = run("scontrol", &["shutdown"], &self.conf);
        std::thread::sleep(Duration::from_secs(2));
        for name in ["slurmctld", "slurmd"] {
            let _ = Command::new("pkill")
                .args(["-f", &format!("{name} -f {}", self.conf.display())])
                .status();
        }
        if let Some(pid) = self.munged {
            let _ = Command::new("kill").arg(pid.to_string()).status();
        }
    }
}

/// munge for authentication: started (with a key) unless one already answers.
fn munge() -> Option<u32> {
    let works = || {
        Command::new("bash")
            .args(["-c", "munge -n | unmunge > /dev/null"])
            .status()
            .is_ok_and(|s| s.success())
    };
    if works() {
        return None;
    }
    std::fs::create_dir_all("/run/munge").unwrap();
    if !Path::new("/etc/munge/munge.key").exists() {
        let st = Command::new("bash")
            .args(["-c", "mkdir -p /etc/munge && dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 2>/dev/null && chmod 400 /etc/munge/munge.key"])
            .status()
            .unwrap();
        assert!(st.success(), "cannot write a munge key");
    }
    let st = Command::new("munged")
        .arg("--force")
        .status()
        .expect("munged (slurm-wlm installs munge)");
    assert!(st.success());
    std::thread::sleep(Duration::from_secs(1));
    assert!(works(), "munge does not answer");
    let pid = std::fs::read_to_string("/run/munge/munged.pid").ok()?;
    pid.trim().parse().ok()
}

fn start(dir: &Path) -> Cluster {
    let host = String::from_utf8(Command::new("hostname").output().unwrap().stdout)
        .unwrap()
        .trim()
        .to_string();
    for d in ["state", "spool", "log"] {
        std::fs::create_dir_all(dir.join(d)).unwrap();
    }
    let d = dir.display();
    let conf = dir.join("slurm.conf");
    std::fs::write(
        &conf,
        format!(
            "ClusterName=wovenform\nSlurmctldHost={host}\nSlurmUser=root\nSlurmdUser=root\n\
             AuthType=auth/munge\nStateSaveLocation={d}/state\nSlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\nSlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldLogFile={d}/log/slurmctld.log\nSlurmdLogFile={d}/log/slurmd.log\n\
             SlurmctldPort=16817\nSlurmdPort=16818\nProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\nJobAcctGatherType=jobacct_gather/none\n\
             SelectType=select/cons_tres\nSelectTypeParameters=CR_Core\nMpiDefault=none\n\
             ReturnToService=2\nNodeName={host} CPUs=2 State=UNKNOWN\n\
             PartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP\n"
        ),
    )
    .unwrap();
    let cluster = Cluster {
        munged: munge(),
        conf: conf.clone(),
    };
    let c = conf.to_str().unwrap();
    assert!(
        run("slurmctld", &["-f", c], &conf).status.success(),
        "slurmctld"
    );
    assert!(run("slurmd", &["-f", c], &conf).status.success(), "slurmd");
    let t = Instant::now();
    loop {
        let o = run("sinfo", &["-h", "-o", "%T"], &conf);
        if text(&o).contains("idle") {
            break;
        }
        assert!(
            t.elapsed() < Duration::from_secs(60),
            "the node never came up: {}",
            text(&o)
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    cluster
}

/// The state of job `id` (`scontrol show job`), e.g. RUNNING or COMPLETED.
fn state(id: &str, conf: &Path) -> String {
    let o = run("scontrol", &["show", "job", id], conf);
    let t = text(&o);
    t.split_whitespace()
        .find_map(|w| w.strip_prefix("JobState="))
        .unwrap_or("")
        .to_string()
}

#[test]
#[ignore]
fn a_sweep_on_a_single_node_slurm_with_a_requeued_task() {
    let tmp = tempfile::tempdir().unwrap();
    let cluster = start(&tmp.path().join("slurm"));
    let conf = cluster.conf.clone();
    let sweep = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/paper-box-explorer.toml");
    let out = tmp.path().join("cluster");
    let started = Instant::now();
    let o = Command::new(bin())
        .arg("slurm")
        .arg(&sweep)
        .args([
            "--out",
            out.to_str().unwrap(),
            "--tasks",
            "3",
            "--min-task-s",
            "0",
        ])
        .args(["--cpus-per-task", "1", "--submit"])
        .env("SLURM_CONF", &conf)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let said = String::from_utf8_lossy(&o.stdout).to_string();
    let ids: Vec<String> = said
        .split("array job ")
        .nth(1)
        .map(|rest| {
            rest.split(|c: char| !c.is_ascii_digit())
                .filter(|s| !s.is_empty())
                .take(2)
                .map(String::from)
                .collect()
        })
        .unwrap_or_default();
    assert_eq!(ids.len(), 2, "{said}");
    let (array, merge) = (&ids[0], &ids[1]);
    // Requeue task 2 while it runs (a preemption).
    let task = format!("{array}_2");
    let t = Instant::now();
    while state(&task, &conf) != "RUNNING" {
        assert!(
            t.elapsed() < Duration::from_secs(120),
            "task 2 never ran: {}",
            state(&task, &conf)
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    std::thread::sleep(Duration::from_millis(500));
    let o = run("scontrol", &["requeue", &task], &conf);
    assert!(o.status.success(), "requeue: {}", text(&o));
    // A requeued job waits out a begin time (about two minutes); let it start now.
    let _ = run(
        "scontrol",
        &["update", &format!("JobId={task}"), "StartTime=now"],
        &conf,
    );
    // The merge runs once the whole array has ended well.
    let t = Instant::now();
    loop {
        let s = state(merge, &conf);
        if s == "COMPLETED" {
            break;
        }
        assert!(
            !["FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL"].contains(&s.as_str()),
            "merge {s}: {}",
            std::fs::read_to_string(out.join("slurm/logs/merge.out")).unwrap_or_default()
        );
        assert!(t.elapsed() < Duration::from_secs(600), "merge still {s}");
        std::thread::sleep(Duration::from_millis(500));
    }
    let cluster_s = started.elapsed().as_secs_f64();
    let local = tmp.path().join("local");
    let started = Instant::now();
    let o = Command::new(bin())
        .arg("sweep")
        .arg(&sweep)
        .args(["--out", local.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    eprintln!(
        "single-node Slurm: {cluster_s:.1} s from submission to the merged sweep; local sweep: {:.1} s",
        started.elapsed().as_secs_f64()
    );
    let (n_cluster, cluster_rows) = rows(&out);
    let (n_local, local_rows) = rows(&local);
    assert_eq!(n_local, 8);
    assert_eq!(n_cluster, 8, "each design once");
    assert_eq!(cluster_rows, local_rows);
    // The requeued task ran twice: its log says so.
    let log = std::fs::read_to_string(out.join("slurm/logs/shard-2.out")).unwrap_or_default();
    eprintln!("task 2's log:\n{log}");
    drop(cluster);
}
