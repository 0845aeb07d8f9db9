//! `wovenform slurm` with hostile names: a line break, `%`, spaces, quotes, `$()`,
//! backticks, `;`, `#`, `\` and the like in the sweep file's name, its folder, the output
//! folder, a `--set` value and the program's own path. For each name, listed or drawn at
//! random, the command either refuses it with exit 2 before writing anything (exactly where no
//! script can hold it: Slurm's `--output` folder, a `--set` split over lines), or writes
//! scripts whose `#SBATCH` block, read as sbatch reads it, holds every directive with the
//! exact value, which `bash -n` accepts, and whose commands, run by bash, call exactly the
//! program, the sweep and the folders given and nothing else (no file `PWNED` appears).

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use wovenform::study::slurm::job_name;

/// Names written to hurt: each is put in one place at a time.
const LISTED: &[&str] = &[
    " ",
    "a b",
    "\n",
    "\nrm x\n#SBATCH --array=1-99\n",
    "%",
    "%a%j",
    "'",
    "\"",
    "\"'",
    "$(touch PWNED)",
    "`touch PWNED`",
    ";touch PWNED;",
    "&& touch PWNED #",
    "# x",
    "\\",
    "\\\"",
    "\t",
    "\r",
    "-x",
    "--out=y",
    "*?[a]",
    "~",
    "${HOME}",
    "é ü",
    ":x",
];

/// Characters of the random names.
const ALPHABET: &[char] = &[
    ' ', '\n', '%', '\'', '"', '$', '(', ')', '`', ';', '#', '\\', '\t', '&', '|', '*', '?', '~',
    '-', '=', ':', 'a', 'Z', '0', 'é', '\r', '!', '{', '}', '<', '>', '\u{7f}',
];

/// The listed names and 40 random ones (a fixed seed: the same names every run).
fn names() -> Vec<String> {
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut all: Vec<String> = LISTED.iter().map(|s| s.to_string()).collect();
    for _ in 0..40 {
        let len = 1 + next() % 6;
        all.push(
            (0..len)
                .map(|_| ALPHABET[(next() % ALPHABET.len() as u64) as usize])
                .collect(),
        );
    }
    all
}

/// Where a name goes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Place {
    SweepName,
    SweepFolder,
    Out,
    Set,
    Binary,
}

/// The cases of one place: its folder, the program, the sweep, the output, the --set values.
struct Case {
    dir: PathBuf,
    binary: PathBuf,
    sweep: PathBuf,
    out: PathBuf,
    sets: Vec<String>,
}

fn presets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("presets")
}

/// Lays out a case with `name` in `place`, under `root/i`.
fn case(root: &Path, i: usize, place: Place, name: &str) -> Case {
    let dir = root.join(i.to_string());
    let pick = |p: Place, base: &str| {
        if p == place {
            format!("{base}{name}x")
        } else {
            base.to_string()
        }
    };
    let sweep_dir = dir.join(pick(Place::SweepFolder, "in"));
    std::fs::create_dir_all(&sweep_dir).unwrap();
    let sweep = sweep_dir.join(pick(Place::SweepName, "sweep") + ".toml");
    std::fs::copy(presets().join("paper-box-explorer.toml"), &sweep).unwrap();
    std::fs::copy(
        presets().join("paper-box-open.toml"),
        sweep_dir.join("paper-box-open.toml"),
    )
    .unwrap();
    let bin_dir = dir.join(pick(Place::Binary, "bin"));
    std::fs::create_dir_all(&bin_dir).unwrap();
    let binary = bin_dir.join("wovenform");
    // A hard link: the program's path is the name it was started by.
    if std::fs::hard_link(env!("CARGO_BIN_EXE_wovenform"), &binary).is_err() {
        std::fs::copy(env!("CARGO_BIN_EXE_wovenform"), &binary).unwrap();
    }
    let mut sets = vec!["process.stroke=28.0".to_string()];
    if place == Place::Set {
        // A TOML comment after the value: the scene takes it, the script must keep it whole.
        sets.push(format!("blank.size=170.0 #{name}"));
    }
    Case {
        out: dir.join(pick(Place::Out, "out")),
        dir,
        binary,
        sweep,
        sets,
    }
}

/// Whether `place` must refuse `name` (no script can hold it there), and what the refusal
/// must say: the option, and one of the ways it says what it expects.
fn refusal(place: Place, name: &str) -> Option<(&'static str, &'static [&'static str])> {
    let control = name.chars().any(char::is_control);
    match place {
        Place::Out if control || name.contains(['%', '\\']) => {
            Some(("--out", &["expected a folder path without"]))
        }
        // A line break splits a --set; TOML comments hold no control character but a tab.
        Place::Set if name.chars().any(|c| c.is_control() && c != '\t') => Some((
            "--set",
            &["one KEY=VALUE per --set", "expected a TOML literal"],
        )),
        _ => None,
    }
}

/// C's `isspace` in the C locale, as sbatch splits a directive line.
fn c_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | 0x0b | 0x0c | b'\r')
}

/// The words of one `#SBATCH` line after the magic word, as sbatch reads them: quotes (either
/// kind) group, a backslash escapes the next character, an unquoted `#` ends the line, an
/// empty word ends it too. `None`: a quote left open or a word starting with `:` (sbatch
/// stops with an error).
fn directive_words(line: &[u8]) -> Option<Vec<String>> {
    let mut words = Vec::new();
    let mut at = 0;
    loop {
        while at < line.len() && c_space(line[at]) {
            at += 1;
        }
        if at == line.len() {
            return Some(words);
        }
        if line[at] == b':' {
            return None;
        }
        let (mut word, mut quote, mut escaped) = (Vec::new(), None, false);
        while at < line.len() && (quote.is_some() || !c_space(line[at])) {
            let b = line[at];
            at += 1;
            match (escaped, b, quote) {
                (true, _, _) => {
                    escaped = false;
                    word.push(b);
                }
                (false, b'\\', _) => escaped = true,
                (false, _, Some(q)) if b == q => quote = None,
                (false, _, Some(_)) => word.push(b),
                (false, b'"' | b'\'', None) => quote = Some(b),
                (false, b'#', None) => {
                    at = line.len();
                    break;
                }
                (false, _, None) => word.push(b),
            }
        }
        if quote.is_some() {
            return None;
        }
        if word.is_empty() {
            return Some(words);
        }
        words.push(String::from_utf8(word).unwrap());
    }
}

/// The options of a script's `#SBATCH` block as sbatch reads it: the lines up to the first
/// one that is neither blank nor a comment.
fn sbatch_options(script: &str) -> Option<Vec<String>> {
    let mut options = Vec::new();
    for line in script.as_bytes().split(|&b| b == b'\n') {
        if let Some(rest) = line.strip_prefix(b"#SBATCH") {
            options.extend(directive_words(rest)?);
            continue;
        }
        match line.iter().find(|&&b| !c_space(b)) {
            None | Some(b'#') => continue,
            Some(_) => break,
        }
    }
    Some(options)
}

/// The words `exec` is called with when bash runs `script` (in `cwd`, `exec` a function that
/// prints them), NUL-separated.
fn exec_words(script: &Path, cwd: &Path) -> Vec<String> {
    let o = Command::new("bash")
        .args(["-c", "exec() { printf '%s\\0' \"$@\"; }; source \"$0\""])
        .arg(script)
        .current_dir(cwd)
        .env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_CPUS_PER_TASK", "2")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let mut words: Vec<String> = o
        .stdout
        .split(|&b| b == 0)
        .map(|w| String::from_utf8(w.to_vec()).unwrap())
        .collect();
    assert_eq!(words.pop().as_deref(), Some(""), "{words:?}");
    words
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn s(p: &Path) -> String {
    p.to_str().unwrap().to_string()
}

/// `submit.sh` run with a stand-in sbatch: the words of each of its calls.
fn sbatch_calls(submit: &Path, cwd: &Path) -> Vec<Vec<String>> {
    let fake = cwd.join("fake-bin");
    let log = cwd.join("sbatch-calls");
    std::fs::create_dir_all(&fake).unwrap();
    std::fs::create_dir_all(&log).unwrap();
    let sbatch = fake.join("sbatch");
    // Call N's words go NUL-separated to SBATCH_LOG/N; it answers as --parsable does.
    std::fs::write(
        &sbatch,
        "#!/bin/bash\nn=$(( $(ls \"$SBATCH_LOG\" | wc -l) + 1 ))\nprintf '%s\\0' \"$@\" > \"$SBATCH_LOG/$n\"\necho \"$((4000 + n));cluster\"\n",
    )
    .unwrap();
    std::fs::set_permissions(&sbatch, std::fs::Permissions::from_mode(0o755)).unwrap();
    let path = format!("{}:{}", fake.display(), std::env::var("PATH").unwrap());
    let o = Command::new("bash")
        .arg(submit)
        .current_dir(cwd)
        .env("PATH", path)
        .env("SBATCH_LOG", &log)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("array job 4001, merge job 4002"),
        "{}",
        text(&o)
    );
    let calls = std::fs::read_dir(&log).unwrap().count();
    (1..=calls)
        .map(|n| {
            let words = std::fs::read(log.join(n.to_string())).unwrap();
            let mut w: Vec<String> = words
                .split(|&b| b == 0)
                .map(|w| String::from_utf8(w.to_vec()).unwrap())
                .collect();
            w.pop();
            w
        })
        .collect()
}

/// Checks the scripts written for `c`: the directives, `bash -n`, the commands.
fn check_scripts(c: &Case, what: &str, tasks: usize) {
    let scripts = c.out.join("slurm");
    let stem = c.sweep.file_stem().unwrap().to_string_lossy().to_string();
    let name = job_name(&stem);
    assert!(!name.contains(|ch: char| ch.is_whitespace() || ch.is_control()));
    let out = s(&c.out);
    let header = |job: &str, log: &str| {
        vec![
            format!("--job-name={name}-{job}"),
            "--cpus-per-task=2".to_string(),
            format!("--output={out}/slurm/logs/{log}"),
            "--partition=debug".to_string(),
            "--time=00:10:00".to_string(),
        ]
    };
    let mut array_options = header("shards", "shard-%a.out");
    array_options.extend([format!("--array=1-{tasks}"), "--requeue".into()]);
    let binary = s(&std::fs::canonicalize(&c.binary).unwrap());
    let mut task = vec![binary.clone(), "sweep".into(), s(&c.sweep), "--out".into()];
    task.extend([format!("{out}/shards/1"), "--shard".into()]);
    task.extend([format!("1/{tasks}"), "--jobs".into(), "2".into()]);
    task.push("--resume".into());
    task.extend(c.sets.iter().map(|v| format!("--set={v}")));
    task.push("--accuracy=coarse".into());
    let mut merge = vec![binary, "merge".into()];
    merge.extend((1..=tasks).map(|i| format!("{out}/shards/{i}")));
    merge.extend(["--out".to_string(), out.clone()]);
    for (file, options, words) in [
        ("array.sh", array_options, task),
        ("merge.sh", header("merge", "merge.out"), merge),
    ] {
        let path = scripts.join(file);
        let script = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            sbatch_options(&script),
            Some(options),
            "{what}: {file}'s #SBATCH block:\n{script}"
        );
        let syntax = Command::new("bash").arg("-n").arg(&path).output().unwrap();
        assert!(syntax.status.success(), "{what}: {file}: {}", text(&syntax));
        assert_eq!(
            exec_words(&path, &c.dir),
            words,
            "{what}: {file}:\n{script}"
        );
    }
    let calls = sbatch_calls(&scripts.join("submit.sh"), &c.dir);
    let array = format!("{out}/slurm/array.sh");
    let merge = format!("{out}/slurm/merge.sh");
    assert_eq!(
        calls,
        [
            vec!["--parsable".to_string(), array],
            vec![
                "--parsable".into(),
                "--dependency=afterok:4001".into(),
                merge
            ]
        ],
        "{what}: submit.sh"
    );
}

/// Every name in `place`: refused where it may be (exit 2, the option named, nothing
/// written), otherwise written safely.
fn hostile(place: Place) {
    let root = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    let tasks = 2;
    for (i, name) in names().iter().enumerate() {
        let what = format!("{place:?} with {name:?}");
        let c = case(root.path(), i, place, name);
        let mut cmd = Command::new(&c.binary);
        cmd.arg("slurm").arg(&c.sweep).arg("--out").arg(&c.out);
        for v in &c.sets {
            cmd.arg(format!("--set={v}"));
        }
        let o = cmd
            .args(["--tasks", &tasks.to_string(), "--min-task-s", "0"])
            .args(["--cpus-per-task", "2", "--partition", "debug"])
            .args(["--time", "00:10:00", "--accuracy", "coarse"])
            .current_dir(&c.dir)
            .output()
            .unwrap();
        match refusal(place, name) {
            Some((option, expected)) => {
                assert_eq!(o.status.code(), Some(2), "{what}: {}", text(&o));
                let err = String::from_utf8_lossy(&o.stderr);
                assert!(
                    err.contains(option) && expected.iter().any(|e| err.contains(e)),
                    "{what}: {err}"
                );
                assert!(!c.out.exists(), "{what}: written before the refusal");
            }
            None => {
                assert!(o.status.success(), "{what}: {}", text(&o));
                check_scripts(&c, &what, tasks);
            }
        }
        assert!(
            !c.dir.join("PWNED").exists() && !c.out.join("PWNED").exists(),
            "{what}: an injected command ran"
        );
    }
}

#[test]
fn hostile_sweep_file_names() {
    hostile(Place::SweepName);
}

#[test]
fn hostile_sweep_folders() {
    hostile(Place::SweepFolder);
}

#[test]
fn hostile_output_folders() {
    hostile(Place::Out);
}

#[test]
fn hostile_set_values() {
    hostile(Place::Set);
}

#[test]
fn hostile_program_paths() {
    hostile(Place::Binary);
}

#[test]
fn a_path_that_is_not_utf8_is_refused() {
    let root = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    let out = root.path().join(OsStr::from_bytes(b"out\xff"));
    let o = Command::new(env!("CARGO_BIN_EXE_wovenform"))
        .arg("slurm")
        .arg(presets().join("paper-box-explorer.toml"))
        .arg("--out")
        .arg(&out)
        .args(["--tasks", "2"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--out") && text(&o).contains("UTF-8"));
    assert!(!out.exists());
}
