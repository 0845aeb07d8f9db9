//! The real binary in a real terminal: tmux (send-keys, capture-pane) drives the explorer
//! through open, run a small sweep, sort, open a detail, export, quit, and reads the screen.
//! The paper's verdicts are the outside answer: the tight design (5/6/5) is infeasible, the
//! open one (10/15/10) feasible. Needs tmux (`.ci/run` installs it).

mod common;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// A tmux server of our own (its own socket), killed when dropped.
struct Tmux {
    socket: String,
}

impl Tmux {
    fn start(name: &str, dir: &Path, command: &str) -> Tmux {
        let version = Command::new("tmux").arg("-V").output();
        assert!(
            version.is_ok_and(|o| o.status.success()),
            "these tests drive the explorer in tmux: install it (apt-get install tmux; .ci/run does)"
        );
        let t = Tmux {
            socket: format!("wovenform-{name}-{}", std::process::id()),
        };
        let ok = Command::new("tmux")
            .args([
                "-L",
                &t.socket,
                "-f",
                "/dev/null",
                "new-session",
                "-d",
                "-s",
                "t",
            ])
            .args(["-x", "80", "-y", "24", "-c"])
            .arg(dir)
            .arg(command)
            .env_remove("NO_COLOR")
            .env("TERM", "xterm-256color")
            .status()
            .expect("tmux starts");
        assert!(ok.success());
        t
    }

    fn keys(&self, keys: &[&str]) {
        let ok = Command::new("tmux")
            .args(["-L", &self.socket, "send-keys", "-t", "t"])
            .args(keys)
            .status()
            .expect("tmux send-keys");
        assert!(ok.success());
    }

    fn screen(&self) -> String {
        let out = Command::new("tmux")
            .args(["-L", &self.socket, "capture-pane", "-p", "-t", "t"])
            .output()
            .expect("tmux capture-pane");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// Waits until the screen shows `text`; returns the screen.
    fn wait_for(&self, text: &str, timeout_s: u64) -> String {
        self.wait_for_any(&[text.to_string()], timeout_s)
    }

    /// [`Tmux::wait_for`], then the screen a moment later: a capture can catch a frame half
    /// written, with `text` drawn and what is below it not yet.
    fn settled(&self, text: &str, timeout_s: u64) -> String {
        self.wait_for(text, timeout_s);
        std::thread::sleep(Duration::from_millis(300));
        self.screen()
    }

    /// Waits until the screen shows one of `texts`; returns the screen.
    fn wait_for_any(&self, texts: &[String], timeout_s: u64) -> String {
        let start = Instant::now();
        loop {
            let s = self.screen();
            if texts.iter().any(|t| s.contains(t.as_str())) {
                return s;
            }
            assert!(
                start.elapsed() < Duration::from_secs(timeout_s),
                "waited {timeout_s} s for one of {texts:?}; the screen:\n{s}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    fn alive(&self) -> bool {
        Command::new("tmux")
            .args(["-L", &self.socket, "has-session", "-t", "t"])
            .output()
            .is_ok_and(|o| o.status.success())
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .args(["-L", &self.socket, "kill-server"])
            .output();
    }
}

/// The explorer in tmux on the paper's tight and open radii (8 designs) meshed at
/// `element_size` mm, from a sweep file `file` written into `dir`.
fn explorer_on_the_paper_grid(name: &str, dir: &Path, file: &str, element_size: f64) -> Tmux {
    let sweep = format!(
        "# The paper's tight and open radii.\nbase = {:?}\n\n[scene.mesh]\nelement_size = {element_size:?}\n\n[sweep]\nr = [5.0, 10.0]\nrp = [6.0, 15.0]\nrm = [5.0, 10.0]\n",
        common::preset("paper-box-open.toml")
    );
    std::fs::write(dir.join(file), sweep).unwrap();
    let command = format!("{} tui {file}", env!("CARGO_BIN_EXE_wovenform"));
    Tmux::start(name, dir, &command)
}

/// The line of the results table of design `index`.
fn design_line(screen: &str, index: usize) -> String {
    screen
        .lines()
        .find(|l| l.starts_with(&format!("│{index}  ")))
        .unwrap_or_else(|| panic!("no line for design {index}:\n{screen}"))
        .to_string()
}

#[test]
fn a_session_open_run_sort_detail_export_quit() {
    let dir = tempfile::tempdir().unwrap();
    // The standard mesh: long enough to be seen running.
    let t = explorer_on_the_paper_grid("session", dir.path(), "small.toml", 2.5);

    let s = t.wait_for("ready: r runs 8 designs", 20);
    println!("— opened:\n{s}");
    assert!(s.contains("standard (2.5 mm)"), "{s}");

    t.keys(&["r"]);
    let s = t.wait_for("running:", 20);
    println!("— running:\n{s}");
    // The interface answers while the workers run: the help opens and closes.
    t.keys(&["?"]);
    t.wait_for("Help", 5);
    t.keys(&["Escape"]);
    let s = t.settled("finished: 8/8", 180);
    println!("— finished:\n{s}");
    assert!(design_line(&s, 0).contains("✗ shear"), "{s}");
    assert!(design_line(&s, 7).contains("✓ feasible"), "{s}");

    // Sort by the max shear (#, r, rp, rm, friction, holder_pressure, shear): the open
    // design, the least sheared, comes first.
    t.keys(&["s", "s", "s", "s", "s", "s"]);
    let s = t.settled("sort: shear ↑", 5);
    println!("— sorted by shear:\n{s}");
    let first = s
        .lines()
        .skip_while(|l| !l.contains("shear°"))
        .nth(1)
        .unwrap_or_default();
    assert!(first.starts_with("│7  "), "{s}");

    // Its detail: the verdict, the figures and the map in half blocks.
    t.keys(&["Enter"]);
    let s = t.settled("Detail", 5);
    println!("— detail:\n{s}");
    assert!(s.contains("Detail"), "{s}");
    assert!(s.contains("design 7 · r 10, rp 15, rm 10 mm"), "{s}");
    assert!(s.contains("✓ feasible"), "{s}");
    assert!(s.contains("60° locking"), "{s}");
    assert!(s.contains('▀'), "{s}");
    t.keys(&["Escape"]);

    // Export.
    t.keys(&["e"]);
    let s = t.wait_for("Export to folder", 5);
    assert!(s.contains("small-export"), "{s}");
    t.keys(&["Enter"]);
    let s = t.settled("exported to", 60);
    println!("— exported:\n{s}");
    let out = dir.path().join("small-export");
    for f in ["results.csv", "results.json", "report.png", "maps"] {
        assert!(out.join(f).exists(), "{f} not written");
    }
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 9, "{csv}");

    t.keys(&["q"]);
    let start = Instant::now();
    while t.alive() && start.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(100));
    }
    assert!(!t.alive(), "the explorer did not quit");
}

#[test]
fn no_argument_opens_the_default_and_quit_restores_the_terminal() {
    let dir = tempfile::tempdir().unwrap();
    // A shell keeps the pane after the explorer quits, so that the restored screen can be read.
    let command = format!(
        "sh -c '{}; echo explorer exited with $?; sleep 60'",
        env!("CARGO_BIN_EXE_wovenform")
    );
    let t = Tmux::start("default", dir.path(), &command);
    let s = t.wait_for("ready: r runs 8 designs", 20);
    println!("— wovenform, no argument:\n{s}");
    assert!(s.contains("paper box (default)"), "{s}");
    t.keys(&["q"]);
    let s = t.wait_for("explorer exited with 0", 10);
    // Back on the normal screen: no trace of the explorer's frames.
    assert!(!s.contains("Parameters"), "{s}");
}

#[test]
fn cancel_stops_the_workers_promptly_and_keeps_the_finished_rows() {
    // The default grid on a fine mesh (1.25 mm): 2 to 5 s a design, so that it is still
    // running when one has finished; cancel then.
    let dir = tempfile::tempdir().unwrap();
    let t = explorer_on_the_paper_grid("cancel", dir.path(), "fine.toml", 1.25);
    t.wait_for("ready: r runs 8 designs", 20);
    t.keys(&["r"]);
    let running: Vec<String> = (1..8).map(|k| format!("running: {k}/8")).collect();
    t.wait_for_any(&running, 120);
    t.keys(&["c"]);
    let asked = Instant::now();
    t.wait_for("cancelled after", 10);
    let took = asked.elapsed().as_secs_f64();
    let s = t.settled("cancelled after", 1);
    println!("— cancelled ({took:.2} s after c):\n{s}");
    assert!(took < 5.0, "the workers took {took:.1} s to stop");
    let kept = s
        .lines()
        .filter(|l| l.contains("✗ shear") || l.contains("✓ feasible"))
        .count();
    assert!(kept >= 1, "{s}");
    assert!(s.contains("resumes)"), "{s}");
    t.keys(&["q"]);
}
