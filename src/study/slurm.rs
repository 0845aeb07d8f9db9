//! The Slurm job array of a sweep: one shard of the grid per array task, each task
//! `--resume`-able (a preempted, requeued task picks up where it stopped), and a merge job
//! that waits for the whole array (`afterok`). Plain data in, script text out; the command
//! (`wovenform slurm`) writes and submits them.
//!
//! No name can change a script: a word of a command line is single-quoted for bash (which
//! takes any character there); an `#SBATCH` line is read by sbatch, not bash (quotes group, a
//! backslash escapes the next character, an unquoted `#` starts a comment, a line ends the
//! directive), so its value is double-quoted with `\` and `"` escaped, and a control character,
//! which no directive can hold, is refused. The log paths given to `--output` are file-name
//! patterns for Slurm (`%a` the task, `\` turns the patterns off), so an output folder with `%`
//! or `\` is refused too.

use std::path::{Path, PathBuf};

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
    /// The job's name (the sweep's, see [`job_name`]).
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
    /// A frontier along this key (`wovenform frontier --along KEY`) instead of the grid: each
    /// task searches its shard of the combinations, and the merge job writes the frontier
    /// from the merged runs.
    pub frontier: Option<String>,
}

/// A string of the job that cannot be written into its scripts as it is.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ScriptError {
    #[error(
        "{what} {path:?}: not valid UTF-8; expected a path a script can name exactly (rename it)"
    )]
    NotUtf8 { what: &'static str, path: PathBuf },
    #[error("{what} {text:?}: holds {found}; expected {expected}")]
    Unwritable {
        what: &'static str,
        text: String,
        found: String,
        expected: &'static str,
    },
}

/// What an output folder may hold, as the error says it.
const OUTPUT_FOLDER: &str = "a folder path without line breaks or other control characters, \
     % or \\ (the logs under it are named in #SBATCH --output, where a line break ends the \
     directive, % starts one of Slurm's file-name patterns and \\ turns them off)";

/// What a directive's value may hold, as the error says it.
const DIRECTIVE: &str =
    "no line breaks or other control characters (an #SBATCH line cannot hold them)";

/// A Slurm job name from a sweep file's stem: letters, digits, `.`, `_`, `-` and `+` kept,
/// any other character (a space, a quote, a line break) as `_`, so that the name is one word
/// in squeue's columns.
pub fn job_name(stem: &str) -> String {
    let name: String = stem
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || "._-+".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if name.is_empty() {
        "sweep".into()
    } else {
        name
    }
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

/// A word quoted for bash: inside single quotes every character stands for itself (a line
/// break too); a `'` is closed, escaped and reopened.
pub fn quoted(word: &str) -> String {
    format!("'{}'", word.replace('\'', r"'\''"))
}

/// How the error names a character.
fn named(c: char) -> String {
    match c {
        '\n' => "a line break".into(),
        '%' => "a %".into(),
        '\\' => "a backslash".into(),
        c => format!("the character {c:?}"),
    }
}

fn unwritable(what: &'static str, text: &str, c: char, expected: &'static str) -> ScriptError {
    ScriptError::Unwritable {
        what,
        text: text.to_string(),
        found: named(c),
        expected,
    }
}

/// One `#SBATCH` line, `what` naming its value in an error. A value of plain characters is
/// written as it is; any other is double-quoted with `\` and `"` escaped (sbatch's own
/// reading of the line); a control character cannot be written at all.
fn directive(what: &'static str, option: &str, value: &str) -> Result<String, ScriptError> {
    if let Some(c) = value.chars().find(|c| c.is_control()) {
        return Err(unwritable(what, value, c, DIRECTIVE));
    }
    let plain = |c: char| c.is_ascii_alphanumeric() || "_.,:/+=%-".contains(c);
    Ok(if !value.is_empty() && value.chars().all(plain) {
        format!("#SBATCH --{option}={value}")
    } else {
        let escaped = value.replace('\\', r"\\").replace('"', "\\\"");
        format!("#SBATCH --{option}=\"{escaped}\"")
    })
}

fn utf8<'a>(what: &'static str, path: &'a Path) -> Result<&'a str, ScriptError> {
    path.to_str().ok_or_else(|| ScriptError::NotUtf8 {
        what,
        path: path.to_path_buf(),
    })
}

/// The job's paths as text, each checked to be writable where it goes.
struct Texts<'a> {
    binary: &'a str,
    sweep: &'a str,
    out: &'a str,
}

impl ArrayJob {
    fn texts(&self) -> Result<Texts<'_>, ScriptError> {
        let out = utf8("--out", &self.out)?;
        if let Some(c) = out
            .chars()
            .find(|&c| c.is_control() || c == '%' || c == '\\')
        {
            return Err(unwritable("--out", out, c, OUTPUT_FOLDER));
        }
        Ok(Texts {
            binary: utf8("this program's path", &self.binary)?,
            sweep: utf8("the sweep file", &self.sweep)?,
            out,
        })
    }

    /// The first lines of a script: the job `NAME-job`, its CPUs, its log `OUT/slurm/logs/log`,
    /// its partition and time limit.
    fn header(&self, job: &str, log: &str) -> Result<Vec<String>, ScriptError> {
        let out = self.texts()?.out;
        let mut lines = vec![
            "#!/bin/bash".to_string(),
            directive("the job name", "job-name", &format!("{}-{job}", self.name))?,
            format!("#SBATCH --cpus-per-task={}", self.cpus_per_task),
            directive("--out", "output", &format!("{out}/slurm/logs/{log}"))?,
        ];
        if let Some(p) = &self.partition {
            lines.push(directive("--partition", "partition", p)?);
        }
        if let Some(t) = &self.time {
            lines.push(directive("--time", "time", t)?);
        }
        Ok(lines)
    }

    /// The options passed on to every task, each a quoted word after a space (`--set=VALUE`:
    /// a value that starts with `-` stays a value).
    fn options(&self) -> String {
        let sets = self.sets.iter().map(|s| format!("--set={s}"));
        let accuracy = self.accuracy.iter().map(|a| format!("--accuracy={a}"));
        sets.chain(accuracy)
            .map(|w| format!(" {}", quoted(&w)))
            .collect()
    }

    /// The array: task `I` runs shard `I/N` into `OUT/shards/I`, resuming what is there.
    pub fn array_script(&self) -> Result<String, ScriptError> {
        let t = self.texts()?;
        let mut lines = self.header("shards", "shard-%a.out")?;
        lines.push(format!("#SBATCH --array=1-{}", self.tasks));
        // A preempted task goes back in the queue; --resume keeps what it finished.
        lines.push("#SBATCH --requeue".into());
        lines.push("set -euo pipefail".into());
        lines.push(format!(
            "exec {} {} --out {}/shards/\"$SLURM_ARRAY_TASK_ID\" --shard \"$SLURM_ARRAY_TASK_ID/{}\" --jobs \"${{SLURM_CPUS_PER_TASK:-{}}}\" --resume{}",
            quoted(t.binary),
            self.command(&t),
            quoted(t.out),
            self.tasks,
            self.cpus_per_task,
            self.options()
        ));
        Ok(lines.join("\n") + "\n")
    }

    /// The merge of every shard into `OUT`, once the array has finished.
    pub fn merge_script(&self) -> Result<String, ScriptError> {
        let t = self.texts()?;
        let mut lines = self.header("merge", "merge.out")?;
        lines.push("set -euo pipefail".into());
        let shards: Vec<String> = (1..=self.tasks)
            .map(|i| format!("{}/shards/{i}", quoted(t.out)))
            .collect();
        lines.push(format!(
            "{}{} merge {} --out {}",
            if self.frontier.is_some() { "" } else { "exec " },
            quoted(t.binary),
            shards.join(" "),
            quoted(t.out)
        ));
        if self.frontier.is_some() {
            // Every run is in the merged folder: the frontier resumes them all, runs nothing
            // and writes frontier.csv, frontier.json and frontier.png there.
            lines.push(format!(
                "exec {} {} --out {} --resume{}",
                quoted(t.binary),
                self.command(&t),
                quoted(t.out),
                self.options()
            ));
        }
        Ok(lines.join("\n") + "\n")
    }

    /// The subcommand with the sweep file: `sweep FILE`, or `frontier FILE --along KEY`.
    fn command(&self, t: &Texts) -> String {
        match &self.frontier {
            None => format!("sweep {}", quoted(t.sweep)),
            Some(key) => format!(
                "frontier {} {}",
                quoted(t.sweep),
                quoted(&format!("--along={key}"))
            ),
        }
    }

    /// The two `sbatch` calls, the merge depending on the array.
    pub fn submit_script(&self) -> Result<String, ScriptError> {
        let dir = format!("{}/slurm", self.texts()?.out);
        Ok([
            "#!/bin/bash".to_string(),
            "set -euo pipefail".into(),
            format!(
                "array=$(sbatch --parsable {})",
                quoted(&format!("{dir}/array.sh"))
            ),
            "array=${array%%;*}".into(),
            format!(
                "merge=$(sbatch --parsable \"--dependency=afterok:$array\" {})",
                quoted(&format!("{dir}/merge.sh"))
            ),
            "echo \"array job $array, merge job ${merge%%;*}\"".into(),
        ]
        .join("\n")
            + "\n")
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
            frontier: None,
        }
    }

    #[test]
    fn each_task_runs_its_shard_resumably_and_the_merge_takes_them_all() {
        let j = job();
        let a = j.array_script().unwrap();
        assert!(a.contains("#SBATCH --array=1-4"), "{a}");
        assert!(a.contains("--shard \"$SLURM_ARRAY_TASK_ID/4\""), "{a}");
        assert!(a.contains("--resume"), "{a}");
        assert!(a.contains("'/home/u/big sweep.toml'"), "{a}");
        assert!(
            a.contains("'--set=process.friction=0.25' '--accuracy=fine'"),
            "{a}"
        );
        assert!(a.contains("#SBATCH --partition=short") && a.contains("#SBATCH --time=01:30:00"));
        assert!(
            a.contains("#SBATCH --output=/scratch/u/out/slurm/logs/shard-%a.out"),
            "{a}"
        );
        let m = j.merge_script().unwrap();
        for i in 1..=4 {
            assert!(m.contains(&format!("'/scratch/u/out'/shards/{i}")), "{m}");
        }
        assert!(
            m.contains("merge") && m.contains("--out '/scratch/u/out'"),
            "{m}"
        );
        let s = j.submit_script().unwrap();
        assert!(s.contains("\"--dependency=afterok:$array\""), "{s}");
    }

    #[test]
    fn a_directive_value_is_quoted_as_sbatch_reads_it_and_a_control_character_refused() {
        let mut j = job();
        j.out = "/scratch/u/my \"big\" run #1".into();
        j.name = job_name("big sweep\n'x'");
        assert_eq!(j.name, "big_sweep__x_");
        let a = j.array_script().unwrap();
        assert!(
            a.contains(
                r#"#SBATCH --output="/scratch/u/my \"big\" run #1/slurm/logs/shard-%a.out""#
            ),
            "{a}"
        );
        assert!(a.contains("#SBATCH --job-name=big_sweep__x_-shards"), "{a}");
        j.partition = Some("a\nb".into());
        let e = j.merge_script().unwrap_err().to_string();
        assert!(e.contains("--partition") && e.contains("line break"), "{e}");
    }

    #[test]
    fn an_output_folder_slurm_would_read_as_a_pattern_is_refused() {
        for (out, found) in [
            ("/s/50%", "a %"),
            ("/s/a\\b", "a backslash"),
            ("/s/a\nb", "a line break"),
            ("/s/a\tb", "'\\t'"),
        ] {
            let mut j = job();
            j.out = out.into();
            for e in [j.array_script(), j.merge_script(), j.submit_script()] {
                let e = e.unwrap_err().to_string();
                assert!(e.starts_with("--out") && e.contains(found), "{out:?}: {e}");
                assert!(e.contains("expected a folder path without"), "{e}");
            }
        }
        use std::os::unix::ffi::OsStrExt;
        let mut j = job();
        j.sweep = std::ffi::OsStr::from_bytes(b"/s/\xff.toml").into();
        let e = j.array_script().unwrap_err().to_string();
        assert!(e.contains("the sweep file") && e.contains("UTF-8"), "{e}");
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

    #[test]
    fn job_names_keep_letters_and_digits() {
        assert_eq!(job_name("paper-box_v2.1+x"), "paper-box_v2.1+x");
        assert_eq!(job_name("étude 3"), "étude_3");
        assert_eq!(job_name("a$(rm -rf)`x`;%"), "a__rm_-rf__x___");
        assert_eq!(job_name(""), "sweep");
    }
}
