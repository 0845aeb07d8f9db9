//! The real binary in a real terminal: a pseudo-terminal opened from Rust (`portable-pty`) runs
//! the explorer, keys are written to it as a terminal sends them, and everything it prints is
//! parsed into a screen (`vt100`) that the checks read. Through open, run a small sweep, sort,
//! open a detail, export, quit. The paper's verdicts are the outside answer: the tight design
//! (5/6/5) is infeasible, the open one (10/15/10) feasible. Needs nothing but the Rust
//! toolchain.
//!
//! Every wait polls the parsed screen until what is awaited is there, with a generous timeout;
//! a screen that is read to be checked is also *settled*: unchanged for a moment, so that a
//! frame is never read half drawn.

use crate::common;

use std::io::{ErrorKind, Read, Write};
use std::num::NonZeroU16;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use portable_pty::{Child, CommandBuilder, MasterPty, PtySize, native_pty_system};

const ROWS: u16 = 24;
const COLS: u16 = 80;
/// The keys as a terminal sends them.
const ESCAPE: &str = "\x1b";
const ENTER: &str = "\r";
/// How long a screen must stay unchanged to count as settled (the explorer redraws every
/// 100 ms; a frame is written in well under that).
const STEADY: Duration = Duration::from_millis(300);

/// What the reader thread shares: the parsed screen and whether the terminal has closed.
struct Terminal {
    parser: vt100::Parser,
    closed: bool,
}

/// The explorer in a pseudo-terminal of 80 × 24; killed when dropped if it still runs.
struct Explorer {
    terminal: Arc<Mutex<Terminal>>,
    writer: Box<dyn Write + Send>,
    child: Box<dyn Child + Send + Sync>,
    master: Box<dyn MasterPty + Send>,
    reader: JoinHandle<()>,
}

/// Feeds everything the explorer prints into the parser, until the terminal closes.
fn read_into(mut from: Box<dyn Read + Send>, terminal: Arc<Mutex<Terminal>>) {
    let mut buf = [0u8; 16384];
    loop {
        match from.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => {
                terminal.lock().unwrap().parser.process(&buf[..n]);
            }
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            // EIO once the explorer has exited and the terminal's other side is closed.
            Err(_) => break,
        }
    }
    terminal.lock().unwrap().closed = true;
}

impl Explorer {
    /// Starts the binary with `args` in `dir` (its session folder under `dir` too).
    fn start(dir: &Path, args: &[&str]) -> Explorer {
        let size = PtySize {
            rows: ROWS,
            cols: COLS,
            pixel_width: 0,
            pixel_height: 0,
        };
        let pair = native_pty_system()
            .openpty(size)
            .expect("a pseudo-terminal opens");
        let mut command = CommandBuilder::new(env!("CARGO_BIN_EXE_wovenform"));
        command.args(args);
        command.cwd(dir);
        command.env("TERM", "xterm-256color");
        command.env_remove("NO_COLOR");
        command.env("TMPDIR", dir);
        let child = pair
            .slave
            .spawn_command(command)
            .expect("the explorer starts");
        // Only the explorer holds the terminal's other side: its exit closes the terminal.
        drop(pair.slave);
        let rows = NonZeroU16::new(ROWS).unwrap();
        let cols = NonZeroU16::new(COLS).unwrap();
        let terminal = Arc::new(Mutex::new(Terminal {
            parser: vt100::Parser::new(rows, cols, 0),
            closed: false,
        }));
        let from = pair.master.try_clone_reader().expect("a reader");
        let shared = Arc::clone(&terminal);
        let reader = std::thread::spawn(move || read_into(from, shared));
        let writer = pair.master.take_writer().expect("a writer");
        Explorer {
            terminal,
            writer,
            child,
            master: pair.master,
            reader,
        }
    }

    /// Types `keys` (each character a key; [`ESCAPE`] and [`ENTER`] as a terminal sends them).
    fn keys(&mut self, keys: &str) {
        self.writer
            .write_all(keys.as_bytes())
            .expect("keys written");
        self.writer.flush().expect("keys sent");
    }

    /// The screen as text, a line per row, and whether the terminal has closed.
    fn screen(&self) -> (String, bool) {
        let t = self.terminal.lock().unwrap();
        let lines: Vec<String> = t
            .parser
            .screen()
            .rows(0, COLS)
            .map(|l| l.trim_end().to_string())
            .collect();
        (lines.join("\n"), t.closed)
    }

    /// Polls the screen until `done(screen, steady)` holds, `steady` how long the screen has
    /// stayed as it is; panics with the screen after `timeout_s` or when the explorer has
    /// exited first.
    fn poll(&self, what: &str, timeout_s: u64, done: impl Fn(&str, Duration) -> bool) -> String {
        let start = Instant::now();
        let (mut last, mut since) = (String::new(), Instant::now());
        loop {
            let (s, closed) = self.screen();
            if s != last {
                (last, since) = (s.clone(), Instant::now());
            }
            if done(&s, since.elapsed()) {
                return s;
            }
            assert!(
                !closed,
                "the explorer exited while waiting for {what}:\n{s}"
            );
            assert!(
                start.elapsed() < Duration::from_secs(timeout_s),
                "waited {timeout_s} s for {what}; the screen:\n{s}"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Waits until the screen shows `text`; returns the screen.
    fn wait_for(&self, text: &str, timeout_s: u64) -> String {
        self.poll(&format!("`{text}`"), timeout_s, |s, _| s.contains(text))
    }

    /// Waits until the screen shows one of `texts`; returns the screen.
    fn wait_for_any(&self, texts: &[String], timeout_s: u64) -> String {
        let what = format!("one of {texts:?}");
        self.poll(&what, timeout_s, |s, _| {
            texts.iter().any(|t| s.contains(t.as_str()))
        })
    }

    /// Waits until the screen no longer shows `text`.
    fn wait_for_gone(&self, text: &str, timeout_s: u64) -> String {
        let what = format!("`{text}` to go");
        self.poll(&what, timeout_s, |s, _| !s.contains(text))
    }

    /// Waits until the screen shows `text` and has stayed unchanged for [`STEADY`]: the frame
    /// is whole.
    fn settled(&self, text: &str, timeout_s: u64) -> String {
        let what = format!("`{text}`, settled");
        self.poll(&what, timeout_s, |s, steady| {
            s.contains(text) && steady >= STEADY
        })
    }

    /// Waits for the explorer to exit; its exit code.
    fn exit_code(&mut self, timeout_s: u64) -> u32 {
        let start = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().expect("the explorer's status") {
                return status.exit_code();
            }
            let (s, ..) = self.screen();
            assert!(
                start.elapsed() < Duration::from_secs(timeout_s),
                "the explorer did not quit in {timeout_s} s:\n{s}"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Waits until everything the explorer printed has been parsed (the terminal closed).
    fn drained(&self, timeout_s: u64) -> vt100::Screen {
        let start = Instant::now();
        while !self.reader.is_finished() {
            assert!(
                start.elapsed() < Duration::from_secs(timeout_s),
                "the terminal did not close in {timeout_s} s"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        self.terminal.lock().unwrap().parser.screen().clone()
    }

    /// Whether the terminal is in canonical (line) mode, as a shell leaves it; the explorer
    /// takes it raw.
    fn canonical(&self) -> bool {
        let termios = self.master.get_termios().expect("the terminal's modes");
        format!("{:?}", termios.local_flags).contains("ICANON")
    }
}

impl Drop for Explorer {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// The explorer on the paper's tight and open radii (8 designs) meshed at `element_size` mm,
/// from a sweep file `file` written into `dir`.
fn explorer_on_the_paper_grid(dir: &Path, file: &str, element_size: f64) -> Explorer {
    let sweep = format!(
        "# The paper's tight and open radii.\nbase = {:?}\n\n[scene.mesh]\nelement_size = {element_size:?}\n\n[sweep]\nr = [5.0, 10.0]\nrp = [6.0, 15.0]\nrm = [5.0, 10.0]\n",
        common::preset("paper-box-open.toml")
    );
    std::fs::write(dir.join(file), sweep).unwrap();
    Explorer::start(dir, &["tui", file])
}

/// The line of the results table of design `index`.
fn design_line(screen: &str, index: usize) -> String {
    screen
        .lines()
        .find(|l| {
            // The paper's two designs carry a ★ after their number.
            let rest = l.strip_prefix(&format!("│{index}")).unwrap_or("x");
            rest.starts_with("  ") || rest.starts_with("★ ")
        })
        .unwrap_or_else(|| panic!("no line for design {index}:\n{screen}"))
        .to_string()
}

#[test]
fn a_session_open_run_sort_detail_export_quit() {
    let dir = tempfile::tempdir().unwrap();
    // The standard mesh: long enough to be seen running.
    let mut t = explorer_on_the_paper_grid(dir.path(), "small.toml", 2.5);

    let s = t.settled("ready: r runs 8 designs", 60);
    println!("— opened:\n{s}");
    assert!(s.contains("standard (2.5 mm)"), "{s}");

    t.keys("r");
    let s = t.wait_for("running:", 60);
    println!("— running:\n{s}");
    // The interface answers while the workers run: the help opens and closes.
    t.keys("?");
    t.wait_for("Help", 30);
    t.keys(ESCAPE);
    t.wait_for_gone("┌ Help", 30);
    let s = t.settled("finished: 8/8", 300);
    println!("— finished:\n{s}");
    assert!(design_line(&s, 0).contains("✗ shear"), "{s}");
    // 5/15/10 (59.7° over a cell at standard, ±1.2°): the locking angle lies in its band.
    assert!(design_line(&s, 3).contains("≈ marginal"), "{s}");
    // The open design (56.5°) is below the locking angle by more than its error.
    assert!(design_line(&s, 7).contains("✓ feasible"), "{s}");

    // Sort by the max shear (one press from #): the open design, the least sheared, comes
    // first.
    t.keys("s");
    let s = t.settled("sort: shear ↑", 30);
    println!("— sorted by shear:\n{s}");
    let first = s
        .lines()
        .skip_while(|l| !l.contains("shear°"))
        .nth(1)
        .unwrap_or_default();
    assert!(first.starts_with("│7★ "), "{s}");

    // Its detail: the verdict, the figures and the map in half blocks.
    t.keys(ENTER);
    let s = t.settled("Detail", 30);
    println!("— detail:\n{s}");
    assert!(s.contains("Detail"), "{s}");
    assert!(s.contains("design 7 · r 10, rp 15, rm 10 mm"), "{s}");
    assert!(s.contains("✓ feasible"), "{s}");
    assert!(s.contains("60° locking"), "{s}");
    assert!(s.contains('▀'), "{s}");
    t.keys(ESCAPE);
    t.wait_for_gone("Detail", 30);

    // Export.
    t.keys("e");
    let s = t.settled("Export to folder", 30);
    assert!(s.contains("small-export"), "{s}");
    t.keys(ENTER);
    let s = t.settled("exported to", 120);
    println!("— exported:\n{s}");
    let out = dir.path().join("small-export");
    for f in ["results.csv", "results.json", "report.png", "maps"] {
        assert!(out.join(f).exists(), "{f} not written");
    }
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 9, "{csv}");

    t.keys("q");
    assert_eq!(t.exit_code(30), 0, "the explorer did not quit cleanly");
}

#[test]
fn no_argument_opens_the_default_and_quit_restores_the_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let mut t = Explorer::start(dir.path(), &[]);
    let s = t.settled("ready: r runs 8 designs", 60);
    println!("— wovenform, no argument:\n{s}");
    assert!(s.contains("paper box (default)"), "{s}");
    assert!(
        !t.canonical(),
        "the explorer runs in a canonical (cooked) terminal"
    );
    t.keys("q");
    assert_eq!(t.exit_code(30), 0);
    // Back on the normal screen, in line mode: no trace of the explorer's frames.
    let screen = t.drained(30);
    let s = screen.contents();
    println!("— after quitting:\n{s}");
    assert!(!screen.alternate_screen(), "still on the alternate screen");
    assert!(!s.contains("Parameters"), "{s}");
    assert!(t.canonical(), "the terminal was left raw");
}

#[test]
fn cancel_stops_the_workers_promptly_and_keeps_the_finished_rows() {
    // The default grid on a fine mesh (1.25 mm): 2 to 5 s a design, so that it is still
    // running when one has finished; cancel then.
    let dir = tempfile::tempdir().unwrap();
    let mut t = explorer_on_the_paper_grid(dir.path(), "fine.toml", 1.25);
    t.wait_for("ready: r runs 8 designs", 60);
    t.keys("r");
    let running: Vec<String> = (1..8).map(|k| format!("running: {k}/8")).collect();
    t.wait_for_any(&running, 240);
    t.keys("c");
    let asked = Instant::now();
    t.wait_for("cancelled after", 30);
    let took = asked.elapsed().as_secs_f64();
    let s = t.settled("cancelled after", 30);
    println!("— cancelled ({took:.2} s after c):\n{s}");
    assert!(took < 5.0, "the workers took {took:.1} s to stop");
    let kept = s
        .lines()
        .filter(|l| l.contains("✗ shear") || l.contains("✓ feasible"))
        .count();
    assert!(kept >= 1, "{s}");
    assert!(s.contains("resumes)"), "{s}");
    t.keys("q");
    assert_eq!(t.exit_code(30), 0);
}

#[test]
fn sigterm_and_sighup_restore_the_terminal_and_keep_the_rows() {
    // SIGTERM mid-run (the shell's `kill`), SIGHUP on an idle explorer (a closed window): each
    // ends it with 128 + the signal, the terminal as a shell wants it back.
    let cases = [(libc::SIGTERM, true), (libc::SIGHUP, false)];
    for (signal, mid_run) in cases {
        let dir = tempfile::tempdir().unwrap();
        let mut t = explorer_on_the_paper_grid(dir.path(), "fine.toml", 1.25);
        t.settled("ready: r runs 8 designs", 60);
        if mid_run {
            t.keys("r");
            t.wait_for("running:", 60);
        }
        let pid = t.child.process_id().expect("the explorer's pid");
        // SAFETY: a signal sent to the child this test started (and still holds).
        unsafe { libc::kill(pid as libc::pid_t, signal) };
        assert_eq!(t.exit_code(30), 128 + signal as u32, "signal {signal}");
        let screen = t.drained(30);
        assert!(
            !screen.alternate_screen(),
            "signal {signal}: still on the alternate screen"
        );
        assert!(
            !screen.hide_cursor(),
            "signal {signal}: the cursor is left hidden"
        );
        assert!(t.canonical(), "signal {signal}: the terminal was left raw");
        if mid_run {
            // The session's run folder is there, with its results file, to resume from.
            let said = screen.contents();
            assert!(said.contains("are kept in"), "{said}");
        }
    }
}
