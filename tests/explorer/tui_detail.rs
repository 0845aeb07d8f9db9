//! A design's detail in the explorer: its tension map, re-running it finer, writing its own
//! files; and the break tension judged again without a run.

use crate::tui_common;

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use ratatui::crossterm::event::KeyCode;
use tui_common::*;
use wovenform::accuracy::Accuracy;
use wovenform::tui::app::{App, Command, Focus, Mode};
use wovenform::tui::params::{Parameters, default_source};
use wovenform::tui::worker::Message;

fn verdict(app: &App, i: usize) -> String {
    app.entries()[i]
        .row
        .as_ref()
        .map(|r| r.verdict.word().to_string())
        .unwrap_or_default()
}

/// Edits the parameter on line `line` of the panel to `text`, as a user does: Tab to the
/// parameters, Home to their first line and down to `line`, Enter, the text, Enter, and Tab
/// back to the results.
fn edit(app: &mut App, line: usize, text: &str) {
    if app.focus() == Focus::Results {
        app.on_key(key(KeyCode::Tab));
    }
    app.on_key(key(KeyCode::Home));
    for _ in 0..line {
        app.on_key(key(KeyCode::Down));
    }
    app.on_key(key(KeyCode::Enter));
    for _ in 0..12 {
        app.on_key(key(KeyCode::Backspace));
    }
    type_text(app, text);
    app.on_key(key(KeyCode::Enter));
    app.on_key(key(KeyCode::Tab));
}

#[test]
fn a_new_break_tension_judges_the_rows_again_without_running() {
    let mut app = explorer(false);
    finished_run(&mut app);
    // Design 7: 58.0° and 297 N ± 35 % at standard, so its tension lies in 193 … 401 N.
    assert_eq!(verdict(&app, 7), "FEASIBLE");
    let line = app
        .params()
        .fields
        .iter()
        .position(|f| f.label == "break")
        .expect("a break tension line");
    edit(&mut app, line, "350");
    assert!(!app.edited(), "the table is the edited grid");
    assert_eq!(
        verdict(&app, 7),
        "MARGINAL",
        "350 N lies inside 193 … 401 N"
    );
    assert_eq!(
        app.entries()[7].limits,
        wovenform::verdict::Limits {
            locking_angle_deg: 60.0,
            break_tension_n: 350.0,
            wrinkle_limit_mm: 1.0
        }
    );
    assert!(
        app.status().contains("the break tension of 350 N"),
        "{}",
        app.status()
    );
    edit(&mut app, line, "150");
    assert_eq!(verdict(&app, 7), "INFEASIBLE", "150 N is under 193 N");
    assert!(screen(&app, 120, 30).contains("✗ tension"));
    // Nothing ran: r would resume the same folder, no design to run.
    assert_eq!(app.runs(), 1);
    // A bad value is refused with what was expected.
    assert!(
        app.params()
            .check(line, "-5")
            .unwrap_err()
            .to_string()
            .contains("break_tension_n")
    );
    assert!(
        app.params()
            .check(line, "lots")
            .unwrap_err()
            .to_string()
            .contains("in N")
    );
}

#[test]
fn t_shows_the_yarn_tension_map_scaled_to_the_field() {
    let mut app = explorer(false);
    finished_run(&mut app);
    app.on_key(key(KeyCode::Enter));
    assert_eq!(*app.mode(), Mode::Detail);
    let s = screen(&app, 100, 40);
    assert!(s.contains("shear, cell peak 78.0°"), "{s}");
    assert!(s.contains("60° locking"), "{s}");
    // The figures beside the map: the field's draw-in and share over the locking angle.
    assert!(s.contains("draw-in 12.5 mm"), "{s}");
    app.on_key(key(KeyCode::Char('t')));
    assert_eq!(*app.mode(), Mode::Detail, "t keeps the detail open");
    let s = screen(&app, 100, 40);
    // corner_field's tension is 6 N per degree of shear: its peak 6 × 78 = 468 N.
    assert!(
        s.contains("yarn tension, cell peak 468 N (break 1500 N)"),
        "{s}"
    );
    // The break (1500 N) is far above the field's largest element (under 468 N): the scale
    // ends at the field's largest and says where the break is.
    assert!(s.contains("break 1500 N is off the scale"), "{s}");
    assert!(!s.contains("60° locking"), "{s}");
    app.on_key(key(KeyCode::Char('t')));
    assert!(screen(&app, 100, 40).contains("shear, cell peak 78.0°"));
}

#[test]
fn plus_re_runs_the_selected_design_one_level_finer_in_its_own_folder() {
    let mut app = explorer(false);
    finished_run(&mut app);
    app.on_key(key(KeyCode::End));
    app.on_key(key(KeyCode::Enter));
    let id7 = app.entries()[7].design.id.clone();
    match app.on_key(key(KeyCode::Char('+'))) {
        Command::Start {
            plan,
            dir,
            resume,
            only,
        } => {
            assert_eq!(only, Some(HashSet::from([id7.clone()])));
            assert_eq!(
                plan.base_scene.mesh.element_size, 1.25,
                "fine after standard"
            );
            assert_eq!(dir, PathBuf::from("/session/run-2"));
            assert!(!resume);
        }
        other => panic!("expected a start, got {other:?}"),
    }
    // The parameters' level and the table's grid stay; only design 7 waits.
    assert_eq!(app.params().accuracy, Accuracy::Standard);
    assert_eq!(app.run_dir(), Some(Path::new("/session/run-1")));
    assert!(app.entries()[7].row.is_none() && app.entries()[0].row.is_some());
    // Its finer row arrives, with the fine level's error.
    let mut r = row(&app, 7, (58.3, 301.0, 6490.0, 9.0));
    r.max_shear_err_deg = Some(Accuracy::Fine.error().max_shear_deg);
    app.on_message(Message::Row(Box::new(r)));
    app.on_message(Message::Finished {
        stopped: false,
        wall_s: 9.0,
        error: None,
    });
    assert_eq!(app.entries()[7].accuracy, Some(Accuracy::Fine));
    assert_eq!(app.entries()[7].dir, Some(PathBuf::from("/session/run-2")));
    let s = screen(&app, 100, 40);
    assert!(
        s.contains("run time 9.0 s at fine (1.25 mm elements)"),
        "{s}"
    );
    assert!(s.contains("±0.6°"), "{s}");
    // Fine is the finest level.
    assert_eq!(app.on_key(key(KeyCode::Char('+'))), Command::None);
    assert!(app.status().contains("at fine already"), "{}", app.status());
    // An export writes both folders: the grid's, and the finer run's beside it.
    assert_eq!(
        app.row_dirs(),
        [
            PathBuf::from("/session/run-1"),
            PathBuf::from("/session/run-2")
        ]
    );
    app.on_key(key(KeyCode::Esc));
    app.on_key(key(KeyCode::Char('e')));
    match app.on_key(key(KeyCode::Enter)) {
        Command::Export { from, .. } => assert_eq!(from.len(), 2),
        other => panic!("expected an export, got {other:?}"),
    }
}

#[test]
fn w_asks_for_the_designs_own_files_at_its_level_and_shows_where_they_went() {
    let mut app = explorer(false);
    finished_run(&mut app);
    app.on_key(key(KeyCode::End));
    let id7 = app.entries()[7].design.id.clone();
    let (scene, dir) = match app.on_key(key(KeyCode::Char('w'))) {
        Command::WriteFiles { design, scene, dir } => {
            assert_eq!(design, id7);
            (scene, dir)
        }
        other => panic!("expected the files to be written, got {other:?}"),
    };
    // Design 7 is r/rp/rm = 10/15/10 mm at standard (2.5 mm elements).
    assert_eq!(scene.mesh.element_size, 2.5);
    assert_eq!(dir, PathBuf::from(format!("/session/{id7}-standard")));
    assert!(screen(&app, 160, 48).contains("writing its PNG maps and VTU"));
    // Not twice while it is being written.
    assert_eq!(app.on_key(key(KeyCode::Char('w'))), Command::None);
    let files: Vec<PathBuf> = ["summary.json", "shear.png", "tension.png", "result.vtu"]
        .iter()
        .map(|f| dir.join(f))
        .collect();
    app.on_message(Message::Written {
        design: id7,
        result: Ok(files),
    });
    let s = screen(&app, 160, 48);
    assert!(s.contains(&format!("files in {}", dir.display())), "{s}");
    assert!(s.contains("shear.png,") && s.contains("result.vtu"), "{s}");
}

#[test]
fn the_design_files_worker_writes_what_run_writes() {
    // The open box at coarse (5 mm): a real solve, its four files written where asked.
    let preset =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/paper-box-open.toml");
    let sets: Vec<wovenform::scene::Override> =
        vec!["mesh.element_size=5.0".parse().expect("an override")];
    let text = std::fs::read_to_string(&preset).unwrap();
    let scene = wovenform::scene::Scene::from_toml_str(&text, &preset.display().to_string(), &sets)
        .unwrap();
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().join("design");
    let (tx, rx) = std::sync::mpsc::channel();
    wovenform::tui::worker::start_design_files("d".into(), scene, dir.clone(), tx);
    match rx.recv().expect("the worker reports") {
        Message::Written { design, result } => {
            assert_eq!(design, "d");
            let files = result.expect("written");
            // What `run` writes: every file it may write but the wrinkle map (no bending).
            let names: Vec<String> = (files.iter())
                .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
                .collect();
            let expected: Vec<&str> = (wovenform::publish::RUN_FILES.iter())
                .filter(|f| **f != "wrinkles.png")
                .copied()
                .collect();
            assert_eq!(names.len(), expected.len(), "{names:?}");
            assert!(
                expected.iter().all(|f| names.iter().any(|n| n == f)),
                "{names:?}"
            );
            for f in &files {
                assert!(
                    f.starts_with(&dir) && f.metadata().unwrap().len() > 100,
                    "{f:?}"
                );
            }
            let png = std::fs::read(dir.join("shear.png")).unwrap();
            assert_eq!(&png[1..4], b"PNG");
            let summary: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                    .unwrap();
            // The paper's open box (Figure 11) is feasible at 60°; coarse's shear within ±4°.
            assert_eq!(summary["converged"], true);
            assert!(summary["max_shear_deg"].as_f64().unwrap() < 60.0);
        }
        other => panic!("expected the files, got {other:?}"),
    }
}

#[test]
fn a_field_that_could_not_be_read_is_read_again_later() {
    let session = tempfile::tempdir().unwrap();
    let params = Parameters::new(default_source()).unwrap();
    let mut app = App::new(params, session.path().to_path_buf(), false);
    app.on_key(key(KeyCode::Char('r')));
    let id0 = app.entries()[0].design.id.clone();
    let r = row(&app, 0, FIGURES[0]);
    app.on_message(Message::Row(Box::new(r)));
    // Its file is not there yet (a resumed run renames it when its workers start).
    assert!(matches!(app.field(&id0), Some(Err(_))));
    let run = app.run_dir().map(std::path::Path::to_path_buf).unwrap();
    std::fs::create_dir_all(run.join("fields")).unwrap();
    let field = corner_field(&id0, 78.0, 60.0);
    std::fs::write(
        run.join("fields").join(format!("{id0}.json")),
        serde_json::to_string(&field).unwrap(),
    )
    .unwrap();
    app.on_key(key(KeyCode::Down));
    app.on_key(key(KeyCode::Up));
    assert!(matches!(app.field(&id0), Some(Ok(_))));
}

#[test]
fn a_sweep_on_a_fabric_with_a_shear_law_says_so_in_the_title() {
    let dir = tempfile::tempdir().unwrap();
    let preset =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/box-with-shear.toml");
    let sweep = dir.path().join("s.toml");
    std::fs::write(
        &sweep,
        format!(
            "base = {:?}\n[sweep]\nr = [5.0, 10.0]\n",
            preset.display().to_string()
        ),
    )
    .unwrap();
    let source = wovenform::tui::source_of_file(&sweep).unwrap();
    let app = App::new(
        Parameters::new(source).unwrap(),
        PathBuf::from("/session"),
        false,
    );
    assert!(screen(&app, 100, 24).contains("· shear law"));
    // The default (the paper's fabric) has none.
    assert!(!screen(&explorer(false), 100, 24).contains("shear law"));
}

#[test]
fn the_detail_says_what_the_run_cost_in_load_steps_and_newton_iterations() {
    let mut app = explorer(false);
    app.on_key(key(KeyCode::Char('r')));
    app.on_message(Message::Started { to_run: 8, kept: 0 });
    deliver(&mut app, &[1, 2, 3, 4, 5, 6, 7]);
    let mut r = row(&app, 0, FIGURES[0]);
    r.steps = Some(20);
    r.newton_iterations = Some(195);
    let id = r.design.clone();
    let locking = app.table_plan().base_scene.fabric.locking_angle_deg;
    app.on_message(Message::Row(Box::new(r)));
    app.keep_field(id.clone(), corner_field(&id, FIGURES[0].0, locking));
    app.on_message(Message::Finished {
        stopped: false,
        wall_s: 24.0,
        error: None,
    });
    app.on_key(key(KeyCode::Enter));
    assert_eq!(app.selected_entry().unwrap().design.index, 0);
    let s = screen(&app, 120, 40);
    assert!(s.contains("20 load steps, 195 Newton iterations"), "{s}");
    // A row that does not carry the counts (one kept from an older results.csv) says nothing.
    app.on_key(key(KeyCode::Down));
    assert_eq!(app.selected_entry().unwrap().design.index, 1);
    let s = screen(&app, 120, 40);
    assert!(!s.contains("load steps"), "{s}");
}
