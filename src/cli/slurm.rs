//! `wovenform slurm SWEEP.toml --out DIR --tasks N`: the sweep as a Slurm job array (one
//! shard per task, each resumable) and a merge job that waits for it; `--submit` submits both.

use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Args;

use super::CliError;
use super::scene_args::GridArgs;
use wovenform::study::slurm::{
    ArrayJob, MAX_CPUS_PER_TASK, MAX_TASKS, ScriptError, is_slurm_time, job_name, quoted, tasks_for,
};
use wovenform::study::sweep::Plan;
use wovenform::study::sweep::holds_this_sweep;

#[derive(Args, Debug)]
pub struct SlurmArgs {
    #[command(flatten)]
    pub grid: GridArgs,
    /// Output folder: the shards go to DIR/shards/I, the merged sweep to DIR, the scripts and
    /// logs to DIR/slurm.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Array tasks at most (fewer when the designs are too quick to fill them), 1 to 4000000.
    #[arg(long, value_name = "N")]
    pub tasks: usize,
    /// CPUs per task (each task runs that many designs at once), 1 to 4096.
    #[arg(long, value_name = "C", default_value_t = 1)]
    pub cpus_per_task: usize,
    /// Slurm partition.
    #[arg(long, value_name = "P")]
    pub partition: Option<String>,
    /// Wall-time limit per task, as sbatch --time takes it: MINUTES, MM:SS, HH:MM:SS, D-HH,
    /// D-HH:MM, D-HH:MM:SS or UNLIMITED.
    #[arg(long, value_name = "HH:MM:SS")]
    pub time: Option<String>,
    /// Estimated work per task at least, s: designs too quick to fill --tasks tasks share
    /// fewer (an allocation costs its queueing and start).
    #[arg(long, value_name = "SECONDS", default_value_t = wovenform::study::slurm::MIN_TASK_WORK_S)]
    pub min_task_s: f64,
    /// A frontier along KEY (as `wovenform frontier --along KEY`) instead of the grid: each
    /// task searches a shard of the combinations, the merge job writes the frontier.
    #[arg(long, value_name = "KEY")]
    pub frontier: Option<String>,
    /// Submit the array and the merge with sbatch, and print their job ids.
    #[arg(long)]
    pub submit: bool,
}

/// The runs a frontier's search takes for a combination, about (measured: 2 to 5).
const RUNS_PER_COMBINATION: usize = 3;

fn absolute(p: &Path) -> Result<PathBuf, CliError> {
    std::path::absolute(p)
        .map_err(|e| CliError::bad_input(format!("{}: cannot resolve the path: {e}", p.display())))
}

fn write(path: &Path, text: &str) -> Result<(), CliError> {
    wovenform::files::write_atomic(path, text.as_bytes())
        .map_err(|e| CliError::bad_input(format!("{}: cannot write: {e}", path.display())))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755));
    }
    Ok(())
}

/// Checks the options that Slurm would only refuse at submission.
fn check(args: &SlurmArgs) -> Result<(), CliError> {
    if !(args.min_task_s >= 0.0 && args.min_task_s.is_finite()) {
        return Err(CliError::bad_input(format!(
            "--min-task-s {}: expected a number of seconds ≥ 0",
            args.min_task_s
        )));
    }
    if !(1..=MAX_TASKS).contains(&args.tasks) {
        return Err(CliError::bad_input(format!(
            "--tasks {}: expected 1 to {MAX_TASKS} array tasks (Slurm's largest job array)",
            args.tasks
        )));
    }
    if !(1..=MAX_CPUS_PER_TASK).contains(&args.cpus_per_task) {
        return Err(CliError::bad_input(format!(
            "--cpus-per-task {}: expected 1 to {MAX_CPUS_PER_TASK} (a task's CPUs are on one node)",
            args.cpus_per_task
        )));
    }
    if let Some(t) = args.time.as_deref().filter(|t| !is_slurm_time(t)) {
        return Err(CliError::bad_input(format!(
            "--time {t:?}: expected a Slurm time limit: MINUTES, MINUTES:SECONDS, HH:MM:SS, \
             DAYS-HH, DAYS-HH:MM, DAYS-HH:MM:SS (at most 2^31 - 1 s) or UNLIMITED, \
             e.g. 90, 01:30:00 or 2-00:00:00"
        )));
    }
    if let Some(p) = args.partition.as_deref().filter(|p| {
        p.is_empty()
            || !p
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-.,".contains(c))
    }) {
        return Err(CliError::bad_input(format!(
            "--partition {p:?}: expected a partition name (letters, digits, _ - . ,)"
        )));
    }
    Ok(())
}

/// Refuses an `--out` that holds another sweep, or whose shard folders do: a task would stop
/// on its shard's folder, or the merge at the end on the folder.
fn refuse_other_sweeps(out: &Path, plan: &Plan) -> Result<(), CliError> {
    let mut folders = vec![out.to_path_buf()];
    if let Ok(entries) = std::fs::read_dir(out.join("shards")) {
        let dirs = entries.filter_map(Result::ok).map(|e| e.path());
        folders.extend(dirs.filter(|p| p.is_dir()));
    }
    for dir in folders {
        holds_this_sweep(&dir, plan).map_err(|e| {
            CliError::bad_input(format!(
                "--out {}: {e}; choose another --out, or remove that folder",
                out.display()
            ))
        })?;
    }
    Ok(())
}

/// Runs `sbatch --parsable ARGS SCRIPT` and returns the job id it prints.
fn sbatch(args: &[String], script: &Path) -> Result<String, CliError> {
    let out = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .arg(script)
        .output()
        .map_err(|e| {
            CliError::failed(format!(
                "sbatch: cannot run it ({e}); is this a Slurm login node?"
            ))
        })?;
    if !out.status.success() {
        return Err(CliError::failed(format!(
            "sbatch {} {}: {}",
            args.join(" "),
            script.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.bytes().all(|b| b.is_ascii_digit()) {
        return Err(CliError::failed(format!(
            "sbatch printed no job id: {text:?}"
        )));
    }
    Ok(id)
}

/// The job of `tasks` tasks, from the options.
fn array_job(args: &SlurmArgs, tasks: usize) -> Result<ArrayJob, CliError> {
    let stem = args.grid.sweep.file_stem().unwrap_or_default();
    Ok(ArrayJob {
        name: job_name(&stem.to_string_lossy()),
        binary: std::env::current_exe()
            .map_err(|e| CliError::failed(format!("cannot find this program's path: {e}")))?,
        sweep: absolute(&args.grid.sweep)?,
        out: absolute(&args.out)?,
        sets: args.grid.set.set.clone(),
        accuracy: args.grid.accuracy.accuracy.map(|a| a.name().to_string()),
        tasks,
        cpus_per_task: args.cpus_per_task,
        partition: args.partition.clone(),
        time: args.time.clone(),
        frontier: args.frontier.clone(),
    })
}

/// The three scripts, each with its path `OUT/slurm/NAME.sh`; bad input when a name cannot be
/// written into them.
fn scripts(job: &ArrayJob) -> Result<[(PathBuf, String); 3], CliError> {
    let bad = |e: ScriptError| CliError::bad_input(e.to_string());
    let dir = job.out.join("slurm");
    Ok([
        (dir.join("array.sh"), job.array_script().map_err(bad)?),
        (dir.join("merge.sh"), job.merge_script().map_err(bad)?),
        (dir.join("submit.sh"), job.submit_script().map_err(bad)?),
    ])
}

/// The plan the tasks run, how many runs it holds and the most tasks it can use: a sweep's
/// designs, or for a frontier its lattice's plan, a few runs a combination and no more
/// tasks than combinations (a task searches whole combinations).
fn work_of(plan: Plan, args: &SlurmArgs) -> Result<(Plan, usize, usize), CliError> {
    match &args.frontier {
        None => {
            let n = plan.len();
            Ok((plan, n, MAX_TASKS))
        }
        Some(key) => {
            let lattice =
                wovenform::study::frontier::Lattice::asked_with(&plan, key, "--frontier")?;
            let combos = lattice.combos.len();
            Ok((lattice.plan, RUNS_PER_COMBINATION * combos, combos))
        }
    }
}

/// Says what was written and submits the two jobs with `--submit`, or says how.
fn announce_and_submit(
    args: &SlurmArgs,
    job: &ArrayJob,
    scripts: &[(PathBuf, String); 3],
    designs: usize,
    tasks: usize,
) -> Result<(), CliError> {
    let [(array, _), (merge, _), (submit, _)] = &scripts;
    println!(
        "{}: {designs} {} in {tasks} array task(s) of {} cpus\n{}: the merge into {}, after the array (afterok)",
        array.display(),
        if args.frontier.is_some() {
            "runs (about)"
        } else {
            "designs"
        },
        args.cpus_per_task,
        merge.display(),
        job.out.display()
    );
    if args.submit {
        let array_id = sbatch(&[], array)?;
        let merge_id = sbatch(&[format!("--dependency=afterok:{array_id}")], merge)?;
        println!("array job {array_id}, merge job {merge_id}");
    } else {
        let submit = quoted(&submit.display().to_string());
        println!("submit both with: bash {submit}");
    }
    Ok(())
}

pub fn exec(args: SlurmArgs) -> Result<(), CliError> {
    check(&args)?;
    let plan = args.grid.plan()?;
    let (plan, designs, most) = work_of(plan, &args)?;
    let per_design_s = wovenform::study::estimate::run_seconds(&plan.base_scene);
    let tasks = tasks_for(
        designs,
        per_design_s,
        args.cpus_per_task,
        args.tasks,
        args.min_task_s,
    )
    .min(most);
    let job = array_job(&args, tasks)?;
    let scripts = scripts(&job)?;
    refuse_other_sweeps(&job.out, &plan)?;
    if tasks < args.tasks {
        say_fewer_tasks(&args, designs, per_design_s, tasks);
    }
    write_scripts(&job, &scripts)?;
    announce_and_submit(&args, &job, &scripts, designs, tasks)?;
    Ok(())
}

/// The scripts written into `OUT/slurm`, with the folder for the tasks' logs.
fn write_scripts(job: &ArrayJob, scripts: &[(PathBuf, String)]) -> Result<(), CliError> {
    wovenform::files::claim_folder(&job.out).map_err(|e| CliError::bad_input(e.to_string()))?;
    let logs = job.out.join("slurm").join("logs");
    std::fs::create_dir_all(&logs).map_err(|e| {
        CliError::bad_input(format!("{}: cannot create the folder: {e}", logs.display()))
    })?;
    for (path, text) in scripts {
        write(path, text)?;
    }
    Ok(())
}

/// Why the array has fewer tasks than `--tasks` asked.
fn say_fewer_tasks(args: &SlurmArgs, designs: usize, per_design_s: f64, tasks: usize) {
    eprintln!(
        "--tasks {}: {designs} designs of about {per_design_s:.1} s each on {} cpus a task make \
         {tasks} task(s) of at least {} s of work (--min-task-s)",
        args.tasks, args.cpus_per_task, args.min_task_s
    );
}
