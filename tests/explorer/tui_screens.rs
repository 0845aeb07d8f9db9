//! The explorer's main screens, drawn on ratatui's `TestBackend` and kept as snapshots in
//! `snapshots/`; each is paired with checks whose answer does not come from the drawing code:
//! the design count of the grid (2 × 2 × 2), the ETA at a constant pace, the verdict against
//! the locking angle (60°: 78° is over it, 58.0° under) and the colours of the figures over a
//! limit, the position of the shear peak in the map (the punch corners), the scene's bound on
//! an edited value, the paper's open design in the detail, the keys src/guide/explorer.md documents.

use crate::analytic;
use crate::tui_common;

use ratatui::crossterm::event::KeyCode;
use ratatui::style::Color;
use tui_common::*;
use wovenform::tui::app::{Mode, RunState};
use wovenform::tui::worker::Message;

/// Keeps the screen as a snapshot, its time estimates ("about 1 s") written "about N s": they
/// scale with this machine's measured speed, which a loaded machine doubles (held within
/// 0.25–4×, so one digit here). The estimate itself is checked in `study::estimate`.
fn snapshot(name: &str, text: &str) {
    let mut text = text.to_string();
    for d in 0..=9 {
        text = text.replace(&format!("about {d} s"), "about N s");
    }
    insta::with_settings!({snapshot_path => "../../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!(name, text);
    });
}

/// Where a text occurs on the screen: (column, line).
fn find(screen: &ratatui::buffer::Buffer, text: &str) -> Option<(u16, u16)> {
    let area = screen.area;
    for y in 0..area.height {
        let line: String = (0..area.width).map(|x| screen[(x, y)].symbol()).collect();
        if let Some(byte) = line.find(text) {
            return Some((line[..byte].chars().count() as u16, y));
        }
    }
    None
}

#[test]
fn empty() {
    let app = explorer(false);
    let s = screen(&app, 80, 24);
    assert!(s.contains("8 designs"), "{s}");
    assert!(s.contains("ready: r runs 8 designs"), "{s}");
    // The paper's designs (Figure 11): 5/6/5 is design 0, 10/15/10 design 7 of this grid.
    let starred: Vec<&str> = s
        .lines()
        .filter(|l| l.contains('★'))
        .map(|l| l.trim_start_matches('"'))
        .collect();
    assert_eq!(starred.len(), 3, "the title and two rows: {s}");
    assert!(starred[1].starts_with("│0★  5     6      5 "), "{s}");
    assert!(starred[2].starts_with("│7★  10    15     10 "), "{s}");
    // The radii in mm in the header; the parameters named as in the scene's keys.
    assert!(s.contains("r mm  rp mm  rm mm"), "{s}");
    for label in [
        "r ",
        "rp",
        "rm",
        "friction",
        "holder_pressure",
        "locking",
        "break",
        "accuracy",
    ] {
        assert!(s.contains(label), "{label}: {s}");
    }
    snapshot("tui_empty_80x24", &s);
}

#[test]
fn running_with_partial_results() {
    let mut app = explorer(false);
    press(&mut app, &[KeyCode::Char('r')]);
    app.on_message(Message::Started { to_run: 8, kept: 0 });
    deliver(&mut app, &[0, 4, 7]);
    app.set_now(12.0);
    assert_eq!(*app.run_state(), RunState::Running);
    // 3 done in 12 s: 4 s a design, 5 to go: 20 s.
    assert_eq!(app.eta_s(), Some(analytic::eta_s(3, 8, 12.0)));
    let s = screen(&app, 80, 24);
    assert!(s.contains("3/8 designs, 12 s elapsed, ETA 20 s"), "{s}");
    assert!(s.contains("running: 3/8 done, 1 feasible"), "{s}");
    snapshot("tui_running_80x24", &s);
}

#[test]
fn finished_with_verdicts_coloured_against_the_limits() {
    let mut app = explorer(true);
    finished_run(&mut app);
    let s = screen(&app, 80, 24);
    // The paper: the tight design (5/6/5) over the locking angle, the open one (10/15/10)
    // under it; 58.0° + 1.8° < 60° is the only feasible design here.
    let line_of = |index: usize| {
        s.lines()
            .find(|l| {
                let rest = l.strip_prefix(&format!("\"│{index}")).unwrap_or("x");
                rest.starts_with("  ") || rest.starts_with("★ ")
            })
            .unwrap_or_else(|| panic!("design {index} in {s}"))
            .to_string()
    };
    assert!(line_of(0).contains("78.0") && line_of(0).contains("✗ shear"));
    assert!(line_of(7).contains("58.0") && line_of(7).contains("✓ feasible"));
    assert!(s.contains("finished: 8/8 in 24 s, 1 feasible"), "{s}");
    let b = buffer(&app, 80, 24);
    // (Design 0 is selected, so its line has the selection's colours.)
    let (x, y) = find(&b, "73.8").expect("design 4's shear");
    assert_eq!(b[(x, y)].fg, Color::Red, "over the locking angle: red");
    let (x, y) = find(&b, "58.0").expect("the open design's shear");
    assert_ne!(b[(x, y)].fg, Color::Red);
    let (x, y) = find(&b, "✓ feasible").expect("a feasible verdict");
    assert_eq!(b[(x, y)].fg, Color::Green);
    snapshot("tui_finished_80x24", &s);
}

#[test]
fn detail_of_an_infeasible_design_shows_the_corners_over_the_limit() {
    let mut app = explorer(false);
    press(&mut app, &[KeyCode::Char('r')]);
    app.on_message(Message::Started { to_run: 8, kept: 0 });
    deliver(&mut app, &[0, 7]);
    // Design 0 is the paper's tight design; it is selected first (sorted by number).
    press(&mut app, &[KeyCode::Enter]);
    assert_eq!(*app.mode(), Mode::Detail);
    let s = screen(&app, 80, 24);
    assert!(s.contains("design 0 · r 5, rp 6, rm 5 mm"), "{s}");
    assert!(s.contains("✗ shear"), "{s}");
    assert!(s.contains("max shear 78.0°"), "{s}");
    // Full shade only where the shear passes 60°: near the four punch corners, and the map's
    // four quadrants each hold some (the quarter is mirrored).
    // The map's lines (not the colour bar, which starts at the border).
    let map: Vec<&str> = s
        .lines()
        .filter(|l| l.contains('░') && !l.starts_with("\"│░"))
        .collect();
    assert!(!map.is_empty(), "{s}");
    let full: Vec<(usize, usize)> = map
        .iter()
        .enumerate()
        .flat_map(|(y, l)| {
            l.chars()
                .enumerate()
                .filter(|(_, c)| *c == '█')
                .map(move |(x, _)| (x, y))
        })
        .collect();
    let xs: Vec<usize> = full.iter().map(|p| p.0).collect();
    let ys: Vec<usize> = full.iter().map(|p| p.1).collect();
    let (xmid, ymid) = (
        (xs.iter().min().unwrap() + xs.iter().max().unwrap()) / 2,
        (ys.iter().min().unwrap() + ys.iter().max().unwrap()) / 2,
    );
    for (left, top) in [(true, true), (true, false), (false, true), (false, false)] {
        assert!(
            full.iter()
                .any(|&(x, y)| (x < xmid) == left && (y < ymid) == top),
            "a corner without shear over the limit: {s}"
        );
    }
    // The middle of the blank (the punch's flat face) is not over the limit.
    assert!(!full.contains(&(xmid, ymid)));
    snapshot("tui_detail_infeasible_80x24", &s);
}

#[test]
fn an_invalid_edit_shows_an_inline_message_and_is_never_run() {
    let mut app = explorer(false);
    press(&mut app, &[KeyCode::Tab, KeyCode::Enter]);
    for _ in 0..5 {
        press(&mut app, &[KeyCode::Backspace]);
    }
    type_text(&mut app, "-2, 5");
    let s = screen(&app, 80, 24);
    assert!(s.contains("-2, 5▏ mm ✗"), "{s}");
    assert!(s.contains("tools.r = -2"), "{s}");
    snapshot("tui_edit_error_80x24", &s);
    // Enter does not take it; Esc drops it; the plan is untouched.
    press(&mut app, &[KeyCode::Enter]);
    assert!(matches!(app.mode(), Mode::Editing { error: Some(_), .. }));
    press(&mut app, &[KeyCode::Esc]);
    assert_eq!(app.params().fields[0].text, "5, 10");
    assert_eq!(app.params().plan.len(), 8);
}

#[test]
fn large_terminal_shows_the_detail_beside_the_table() {
    let mut app = explorer(false);
    finished_run(&mut app);
    press(&mut app, &[KeyCode::End]);
    let s = screen(&app, 160, 48);
    assert!(s.contains("Detail"), "{s}");
    assert!(s.contains("design 7 · r 10, rp 15, rm 10 mm"), "{s}");
    assert!(s.contains("60° locking"), "{s}");
    snapshot("tui_finished_160x48", &s);
}

/// The explorer's keys as src/guide/explorer.md documents them, each with a word of what
/// it does: the answer the help screen is checked against.
const README_KEYS: [(&str, &str); 14] = [
    ("Tab", "parameters"),
    ("↑ ↓", "select"),
    ("Enter", "edit"),
    ("← →", "accuracy"),
    ("s S", "sort"),
    ("f", "feasible"),
    ("r", "run"),
    ("c", "cancel"),
    ("e", "export"),
    ("?", "help"),
    ("q", "quit"),
    ("t", "tension"),
    ("+", "finer"),
    ("w", "VTU"),
];

/// The help's entries: inside the help's box, for each line `KEYS  what they do`, the keys
/// and the text.
fn help_entries(screen: &str) -> Vec<(Vec<String>, String)> {
    let lines: Vec<Vec<char>> = screen.lines().map(|l| l.chars().collect()).collect();
    let Some((top, left)) = lines.iter().enumerate().find_map(|(y, l)| {
        let text: String = l.iter().collect();
        let byte = text.find("┌ Help")?;
        Some((y, text[..byte].chars().count()))
    }) else {
        return Vec::new();
    };
    lines[top + 1..]
        .iter()
        .take_while(|l| l.get(left) == Some(&'│'))
        .filter_map(|l| {
            let inner: String = l[left + 1..].iter().take_while(|c| **c != '│').collect();
            let (keys, does) = inner.trim().split_once("  ")?;
            let keys = keys.split([',', ' ']).filter(|k| !k.is_empty());
            Some((keys.map(String::from).collect(), does.trim().to_string()))
        })
        .collect()
}

#[test]
fn help() {
    let mut app = explorer(false);
    press(&mut app, &[KeyCode::Char('?')]);
    let s = screen(&app, 80, 24);
    assert!(s.contains("Help"), "{s}");
    assert!(
        s.contains("cancel: workers stop, finished rows stay"),
        "{s}"
    );
    // Every documented key is on a line of the help, with what it does.
    let entries = help_entries(&s);
    for (keys, does) in README_KEYS {
        let listed = entries.iter().any(|(k, text)| {
            keys.split(' ').all(|key| k.iter().any(|x| x == key)) && text.contains(does)
        });
        assert!(listed, "the help does not list `{keys}` ({does}):\n{s}");
    }
    // Nothing is cut at 80 or 120 columns: every verdict is named and the last word is there.
    for width in [80, 120] {
        let s = screen(&app, width, 24);
        let words: String = s.split_whitespace().collect::<Vec<_>>().join(" ");
        for said in ["≈ marginal", "✗ tension", "- invalid", "closes."] {
            assert!(words.contains(said), "{width} columns: no `{said}`:\n{s}");
        }
    }
    snapshot("tui_help_80x24", &s);
}
