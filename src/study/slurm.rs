//! The Slurm job array of a sweep: one shard of the grid per array task, each task
//! `--resume`-able (a preempted, requeued task picks up where it stopped), and a merge job
//! that waits for the whole array (`afterok`). Plain data in, script text out; the command
//! (`wovenform slurm`) writes and submits them.

use std::path::PathBuf;

/// At least this much estimated work per task, s: tiny designs are not one allocation each.
pub const MIN_TASK_WORK_S: f64 = 120.0;

/// The most array tasks: Slurm's `MaxArraySize` may not exceed 4000001 (task indices up to
/// 4000000), so no cluster runs a larger array.
pub const MAX_TASKS: usize = 4_000_000;

/// The most CPUs per task: a task's CPUs are on one node, and the largest nodes hold well
/// under 4096 hardware threads (two 192-core processors with two threads a core make 768);
/// more is a typo, not a machine.
pub const MAX_CPUS_PER_TASK: usize = 4096;

/// The longest time limit, s: sbatch reads `--time` into a C `int` of seconds.
const MAX_TIME_S: u64 = i32::MAX as u64;

/// What the scripts need.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayJob {
    /// The job's name (the sweep's).
    pub name: String,
    /// The wovenform binary, the sweep file and the output folder, absolute.
    pub binary: PathBuf,
    pub sweep: PathBuf,
    pub out: PathBuf,
    /// `--set` overrides of the base scene and the accuracy level, passed on to every task.
    pub sets: Vec<String>,
    pub accuracy: Option<String>,
    pub tasks: usize,
    pub cpus_per_task: usize,
    pub partition: Option<String>,
    /// Wall-time limit per task, as Slurm writes it (see [`is_slurm_time`]).
    pub time: Option<String>,
}

/// How many tasks to run `designs` designs of about `per_design_s` each in, at most
/// `requested`: each task gets at least `min_task_s` of work on its `cpus` (or one design).
pub fn tasks_for(
    designs: usize,
    per_design_s: f64,
    cpus: usize,
    requested: usize,
    min_task_s: f64,
) -> usize {
    let work_s = designs as f64 * per_design_s / cpus.max(1) as f64;
    let by_work = if min_task_s > 0.0 {
        (work_s / min_task_s).floor().clamp(1.0, usize::MAX as f64) as usize
    } else {
        usize::MAX
    };
    requested.min(designs).min(by_work).max(1)
}

/// Whether `text` is a time limit `sbatch --time` takes: "minutes", "minutes:seconds",
/// "hours:minutes:seconds", "days-hours", "days-hours:minutes" or
/// "days-hours:minutes:seconds" (digits, as many as wanted, up to sbatch's longest limit of
/// 2³¹ − 1 s), or `UNLIMITED` / `INFINITE` in any case.
pub fn is_slurm_time(text: &str) -> bool {
    ["unlimited", "infinite"]
        .iter()
        .any(|w| text.eq_ignore_ascii_case(w))
        || slurm_time_s(text).is_some_and(|s| s <= MAX_TIME_S)
}

/// The seconds of a time limit in one of sbatch's forms; `None` for any other text.
fn slurm_time_s(text: &str) -> Option<u64> {
    // Digits only, leading zeros or not; a number past u64 is past any limit.
    let number = |s: &str| {
        (!s.is_empty() && s.bytes().all(|b| b.is_ascii_digit()))
            .then(|| s.parse::<u64>().ok())
            .flatten()
    };
    let (days, rest) = match text.split_once('-') {
        Some((d, r)) => (Some(number(d)?), r),
        None => (None, text),
    };
    let parts: Vec<u64> = rest.split(':').map(number).collect::<Option<_>>()?;
    // Seconds per unit of each part, by form.
    let units: &[u64] = match (days.is_some(), parts.len()) {
        (false, 1) => &[60],
        (false, 2) => &[60, 1],
        (false, 3) => &[3600, 60, 1],
        (true, 1) => &[3600],
        (true, 2) => &[3600, 60],
        (true, 3) => &[3600, 60, 1],
        _ => return None,
    };
    let mut total = days.unwrap_or(0).checked_mul(86_400)?;
    for (p, u) in parts.iter().zip(units) {
        total = total.checked_add(p.checked_mul(*u)?)?;
    }
    Some(total)
}

/// A word quoted for the shell.
fn quoted(word: &str) -> String {
    format!("'{}'", word.replace('\'', r"'\''"))
}

fn path(p: &std::path::Path) -> String {
    quoted(&p.display().to_string())
}

impl ArrayJob {
    fn header(&self, job: &str) -> Vec<String> {
        let mut lines = vec![
            "#!/bin/bash".to_string(),
            format!("#SBATCH --job-name={}-{job}", self.name),
            format!("#SBATCH --cpus-per-task={}", self.cpus_per_task),
        ];
        if let Some(p) = &self.partition {
            lines.push(format!("#SBATCH --partition={p}"));
        }
        if let Some(t) = &self.time {
            lines.push(format!("#SBATCH --time={t}"));
        }
        lines
    }

    /// The folder of shard `i` (1-based), as the shell reads it.
    pub fn shard_dir(&self, i: &str) -> String {
        format!("{}/shards/{i}", path(&self.out))
    }

    fn options(&self) -> String {
        let mut words = Vec::new();
        for s in &self.sets {
            words.push(format!("--set {}", quoted(s)));
        }
        if let Some(a) = &self.accuracy {
            words.push(format!("--accuracy {a}"));
        }
        words.join(" ")
    }

    /// The array: task `I` runs shard `I/N` into `OUT/shards/I`, resuming what is there.
    pub fn array_script(&self) -> String {
        let mut lines = self.header("shards");
        let logs = self.out.join("slurm").join("logs");
        lines.push(format!("#SBATCH --array=1-{}", self.tasks));
        lines.push(format!("#SBATCH --output={}/shard-%a.out", logs.display()));
        // A preempted task goes back in the queue; --resume keeps what it finished.
        lines.push("#SBATCH --requeue".into());
        lines.push("set -euo pipefail".into());
        lines.push(format!(
            "exec {} sweep {} --out {} --shard \"$SLURM_ARRAY_TASK_ID/{}\" --jobs \"${{SLURM_CPUS_PER_TASK:-{}}}\" --resume {}",
            path(&self.binary),
            path(&self.sweep),
            self.shard_dir("\"$SLURM_ARRAY_TASK_ID\""),
            self.tasks,
            self.cpus_per_task,
            self.options()
        ));
        lines.join("\n") + "\n"
    }

    /// The merge of every shard into `OUT`, once the array has finished.
    pub fn merge_script(&self) -> String {
        let mut lines = self.header("merge");
        let logs = self.out.join("slurm").join("logs");
        lines.push(format!("#SBATCH --output={}/merge.out", logs.display()));
        lines.push("set -euo pipefail".into());
        let shards: Vec<String> = (1..=self.tasks)
            .map(|i| self.shard_dir(&i.to_string()))
            .collect();
        lines.push(format!(
            "exec {} merge {} --out {}",
            path(&self.binary),
            shards.join(" "),
            path(&self.out)
        ));
        lines.join("\n") + "\n"
    }

    /// The two `sbatch` calls, the merge depending on the array.
    pub fn submit_script(&self) -> String {
        let dir = self.out.join("slurm");
        [
            "#!/bin/bash".to_string(),
            "set -euo pipefail".into(),
            format!("array=$(sbatch --parsable {})", path(&dir.join("array.sh"))),
            "array=${array%%;*}".into(),
            format!(
                "merge=$(sbatch --parsable --dependency=afterok:$array {})",
                path(&dir.join("merge.sh"))
            ),
            "echo \"array job $array, merge job ${merge%%;*}\"".into(),
        ]
        .join("\n")
            + "\n"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job() -> ArrayJob {
        ArrayJob {
            name: "big".into(),
            binary: "/opt/wovenform".into(),
            sweep: "/home/u/big sweep.toml".into(),
            out: "/scratch/u/out".into(),
            sets: vec!["process.friction=0.25".into()],
            accuracy: Some("fine".into()),
            tasks: 4,
            cpus_per_task: 2,
            partition: Some("short".into()),
            time: Some("01:30:00".into()),
        }
    }

    #[test]
    fn each_task_runs_its_shard_resumably_and_the_merge_takes_them_all() {
        let j = job();
        let a = j.array_script();
        assert!(a.contains("#SBATCH --array=1-4"), "{a}");
        assert!(a.contains("--shard \"$SLURM_ARRAY_TASK_ID/4\""), "{a}");
        assert!(a.contains("--resume"), "{a}");
        assert!(a.contains("'/home/u/big sweep.toml'"), "{a}");
        assert!(
            a.contains("--set 'process.friction=0.25' --accuracy fine"),
            "{a}"
        );
        assert!(a.contains("#SBATCH --partition=short") && a.contains("#SBATCH --time=01:30:00"));
        let m = j.merge_script();
        for i in 1..=4 {
            assert!(m.contains(&format!("'/scratch/u/out'/shards/{i}")), "{m}");
        }
        assert!(
            m.contains("merge") && m.contains("--out '/scratch/u/out'"),
            "{m}"
        );
        let s = j.submit_script();
        assert!(s.contains("--dependency=afterok:$array"), "{s}");
    }

    #[test]
    fn tiny_designs_share_a_task() {
        // 100 designs of 1 s on 2 cpus: 50 s of work, one task.
        assert_eq!(tasks_for(100, 1.0, 2, 10, MIN_TASK_WORK_S), 1);
        // 100 designs of 30 s on 2 cpus: 1500 s, 12 tasks of 120 s; 10 asked.
        assert_eq!(tasks_for(100, 30.0, 2, 10, MIN_TASK_WORK_S), 10);
        // Never more tasks than designs; no minimum: as asked.
        assert_eq!(tasks_for(3, 1000.0, 1, 10, MIN_TASK_WORK_S), 3);
        assert_eq!(tasks_for(8, 0.1, 1, 3, 0.0), 3);
    }

    #[test]
    fn slurm_times_are_recognised() {
        for ok in [
            "0",
            "30",
            "1440",
            "100000",
            "0000000000000000000000001440",
            "30:00",
            "90:30",
            "01:30:00",
            "100:00:00",
            "2-00",
            "2-12:00",
            "1-01:30:00",
            "365-0",
            "UNLIMITED",
            "unlimited",
            "Infinite",
            "INFINITE",
            // The longest: 2³¹ − 1 s, in minutes (rounded down) and in seconds.
            "35791394",
            "0:2147483647",
        ] {
            assert!(is_slurm_time(ok), "{ok}");
        }
        for bad in [
            "",
            "1h",
            "01:30:00:00",
            "-1",
            "1-",
            "-30",
            "a-01",
            "1:2:3:4",
            "1-2:3:4:5",
            "1-2-3",
            ":30",
            "30:",
            " 30",
            "30 ",
            "+30",
            "01;rm",
            "unlimitedx",
            "forever",
            "35791395",
            "0:2147483648",
            "99999999999999999999999999",
        ] {
            assert!(!is_slurm_time(bad), "{bad}");
        }
    }
}
