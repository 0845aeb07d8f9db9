//! `b` in the explorer: the boundary along the sorted number column (else the first), run by
//! the headless frontier into a run folder of its own; its runs fill the table where they
//! fall on the grid, its boundaries show as lines under the results, the Run panel counts its
//! runs against the grid's, and the detail draws the selected design's combination.

use crate::tui_common;

use std::path::PathBuf;

use ratatui::crossterm::event::KeyCode;
use tui_common::*;
use wovenform::study::frontier::{Boundary, Found, Frontier, Governing, Line, RunPoint};
use wovenform::tui::app::{Command, RunState};
use wovenform::tui::worker::Message;
use wovenform::verdict::{Limits, Verdict};

/// What a frontier along r of the default grid could find: rp 15, rm 10 forms from r 7.4 mm;
/// the other pairs lock over the whole range.
fn found(app: &wovenform::tui::app::App) -> Frontier {
    let mut lines = Vec::new();
    for rp in [6.0, 15.0] {
        for rm in [5.0, 10.0] {
            let values = vec![
                ("rp".into(), "tools.rp".into(), toml::Value::Float(rp)),
                ("rm".into(), "tools.rm".into(), toml::Value::Float(rm)),
            ];
            let found = if rp == 15.0 && rm == 10.0 {
                Found::Boundaries(vec![Boundary {
                    governing: Governing::Shear,
                    value: 7.4,
                    search: [7.2, 7.8],
                    interval: [6.1, 8.6],
                    feasible_above: true,
                }])
            } else {
                Found::Whole {
                    over: vec![Governing::Shear],
                    range: [5.0, 10.0],
                }
            };
            let runs = vec![
                RunPoint {
                    value: 5.0,
                    design: "x".into(),
                    verdict: Verdict::Infeasible,
                },
                RunPoint {
                    value: 10.0,
                    design: "y".into(),
                    verdict: Verdict::Feasible,
                },
            ];
            lines.push(Line {
                values,
                found,
                runs,
                unanswered: Vec::new(),
            });
        }
    }
    Frontier {
        column: "r".into(),
        key: "tools.r".into(),
        range: [5.0, 10.0],
        grid_values: 2,
        log: false,
        limits: Limits::of(&app.table_plan().base_scene),
        lines,
        ran: 8,
        kept: 0,
        rows: Vec::new(),
        wall_s: 3.0,
    }
}

#[test]
fn b_finds_the_boundary_along_r_and_shows_it_under_the_results_and_in_the_detail() {
    let mut app = explorer(false);
    match app.on_key(key(KeyCode::Char('b'))) {
        Command::Frontier {
            lattice,
            dir,
            resume,
        } => {
            assert_eq!(lattice.searched().column, "r");
            assert_eq!(lattice.combos.len(), 4);
            assert_eq!(dir, PathBuf::from("/session/run-1"));
            assert!(!resume, "nothing to keep");
        }
        other => panic!("expected a frontier, got {other:?}"),
    }
    assert_eq!(*app.run_state(), RunState::Running);
    // Not twice at once.
    assert_eq!(app.on_key(key(KeyCode::Char('b'))), Command::None);
    app.on_message(Message::Round { to_run: 8 });
    deliver(&mut app, &[0, 1, 6, 7]);
    assert!(screen(&app, 160, 45).contains("boundary along r: 4 runs so far for 4 combinations"));
    let f = found(&app);
    app.on_message(Message::Frontier(Box::new(f)));
    app.on_message(Message::Finished {
        stopped: false,
        wall_s: 3.0,
        error: None,
    });
    let s = screen(&app, 160, 45);
    for words in [
        "Boundary along r (b)",
        "rp 15 mm, rm 10 mm: r ≥ 7.4 mm (shear) (MARGINAL 6.1–8.6) · 2 runs",
        "rp 6 mm, rm 5 mm: INFEASIBLE over r 5.0–10.0 mm (shear) · 2 runs",
        "boundary along r: 8 runs against the grid's 8 (1.00×)",
    ] {
        assert!(s.contains(words), "{words}:\n{s}");
    }
    // The detail of r 10, rp 15, rm 10 (the last design) draws its combination's chart.
    press(&mut app, &[KeyCode::End, KeyCode::Enter]);
    let s = screen(&app, 100, 50);
    // The chart: its axis (r from 5 to 10 mm) and the boundary, a vertical braille line.
    assert!(
        s.contains("r mm") && s.contains("10.0") && s.contains('⡇'),
        "{s}"
    );
}

#[test]
fn b_searches_the_sorted_column_when_it_is_a_swept_number() {
    let mut app = explorer(false);
    // s from # goes to the figures first; reach rm (the third parameter) by cycling.
    for _ in 0..20 {
        if app.sort_name(app.sort().column) == "rm" {
            break;
        }
        app.on_key(key(KeyCode::Char('s')));
    }
    assert_eq!(app.sort_name(app.sort().column), "rm");
    match app.on_key(key(KeyCode::Char('b'))) {
        Command::Frontier { lattice, .. } => assert_eq!(lattice.searched().column, "rm"),
        other => panic!("expected a frontier, got {other:?}"),
    }
}

#[test]
fn b_after_a_finished_run_keeps_its_rows_and_searches_in_its_folder() {
    let mut app = explorer(false);
    finished_run(&mut app);
    let before: Vec<_> = app.entries().iter().map(|e| e.row.clone()).collect();
    assert!(before.iter().all(Option::is_some));
    match app.on_key(key(KeyCode::Char('b'))) {
        Command::Frontier { dir, resume, .. } => {
            assert_eq!(dir, PathBuf::from("/session/run-1"), "the run's own folder");
            assert!(resume, "its rows are the search's");
        }
        other => panic!("expected a frontier, got {other:?}"),
    }
    let after: Vec<_> = app.entries().iter().map(|e| e.row.clone()).collect();
    assert_eq!(after, before, "no finished row is shown as not run");
    assert_eq!(app.runs(), 1);
}
