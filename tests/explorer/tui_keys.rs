//! The explorer's keys, through its state: what each key changes and which command it asks
//! of the event loop.

use crate::tui_common;

use std::path::PathBuf;

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use tui_common::*;
use wovenform::tui::app::{App, Command, Focus, Mode, RunState};
use wovenform::tui::params::{Parameters, default_source};
use wovenform::tui::worker::Message;

#[test]
fn r_starts_the_grid_in_a_fresh_run_folder_and_not_twice() {
    let mut app = explorer(false);
    match app.on_key(key(KeyCode::Char('r'))) {
        Command::Start {
            plan, dir, resume, ..
        } => {
            assert_eq!(plan.len(), 8);
            assert_eq!(dir, PathBuf::from("/session/run-1"));
            assert!(!resume);
        }
        other => panic!("expected a start, got {other:?}"),
    }
    assert_eq!(*app.run_state(), RunState::Running);
    assert_eq!(app.on_key(key(KeyCode::Char('r'))), Command::None);
    assert!(app.status().contains("running"), "{}", app.status());
}

#[test]
fn cancel_keeps_the_rows_and_r_resumes_the_same_folder() {
    let mut app = explorer(false);
    app.on_key(key(KeyCode::Char('r')));
    app.on_message(Message::Started { to_run: 8, kept: 0 });
    deliver(&mut app, &[0, 7]);
    assert_eq!(app.on_key(key(KeyCode::Char('c'))), Command::Cancel);
    assert_eq!(*app.run_state(), RunState::Stopping);
    app.on_message(Message::Finished {
        stopped: true,
        wall_s: 6.0,
        error: None,
    });
    assert_eq!(*app.run_state(), RunState::Cancelled { wall_s: 6.0 });
    assert_eq!(app.counts(), (2, 1));
    match app.on_key(key(KeyCode::Char('r'))) {
        Command::Start { dir, resume, .. } => {
            assert!(resume);
            assert_eq!(dir, PathBuf::from("/session/run-1"));
        }
        other => panic!("expected a resume, got {other:?}"),
    }
    // The rows stay on the table while the rest runs.
    assert_eq!(app.counts(), (2, 1));
}

#[test]
fn after_a_cancel_another_accuracy_is_a_new_run_not_a_resume() {
    let mut app = explorer(false);
    app.on_key(key(KeyCode::Char('r')));
    app.on_message(Message::Started { to_run: 8, kept: 0 });
    deliver(&mut app, &[0, 7]);
    app.on_key(key(KeyCode::Char('c')));
    app.on_message(Message::Finished {
        stopped: true,
        wall_s: 6.0,
        error: None,
    });
    // The accuracy one level down (the last parameter, ←): the scene is another one, so its
    // rows cannot be resumed into the cancelled run's folder (which used to fail).
    press(&mut app, &[KeyCode::Tab, KeyCode::End, KeyCode::Left]);
    match app.on_key(key(KeyCode::Char('r'))) {
        Command::Start {
            dir, resume, plan, ..
        } => {
            assert!(!resume);
            assert_eq!(dir, PathBuf::from("/session/run-2"));
            assert_eq!(plan.base_scene.mesh.element_size, 5.0);
        }
        other => panic!("expected a new run, got {other:?}"),
    }
}

#[test]
fn editing_checks_as_you_type_and_commits_only_valid_values() {
    let mut app = explorer(false);
    app.on_key(key(KeyCode::Tab));
    assert_eq!(app.focus(), Focus::Parameters);
    app.on_key(key(KeyCode::Down)); // rp
    app.on_key(key(KeyCode::Enter));
    assert_eq!(
        *app.mode(),
        Mode::Editing {
            buffer: "6, 15".into(),
            error: None
        }
    );
    type_text(&mut app, ", 40");
    // rp = 40 mm cannot fit the 28 mm stroke of a 60 mm punch: the scene says why.
    let Mode::Editing { error: Some(e), .. } = app.mode() else {
        panic!("expected an error, got {:?}", app.mode())
    };
    assert!(e.to_string().contains("tools.rp"), "{e}");
    app.on_key(key(KeyCode::Enter));
    assert!(matches!(app.mode(), Mode::Editing { error: Some(_), .. }));
    for _ in 0..4 {
        app.on_key(key(KeyCode::Backspace));
    }
    type_text(&mut app, ", 10.5");
    assert!(matches!(app.mode(), Mode::Editing { error: None, .. }));
    app.on_key(key(KeyCode::Enter));
    assert_eq!(*app.mode(), Mode::Normal);
    assert_eq!(app.params().fields[1].text, "6, 15, 10.5");
    // Nothing ran yet: the table follows the edit.
    assert_eq!(app.entries().len(), 12);
    // Accuracy by ← →.
    app.on_key(key(KeyCode::End));
    app.on_key(key(KeyCode::Left));
    assert_eq!(app.params().plan.base_scene.mesh.element_size, 5.0);
    app.on_key(key(KeyCode::Right));
    app.on_key(key(KeyCode::Right));
    assert_eq!(app.params().plan.base_scene.mesh.element_size, 1.25);
}

#[test]
fn editing_after_a_run_marks_the_table_as_the_previous_grid() {
    let mut app = explorer(false);
    finished_run(&mut app);
    press(
        &mut app,
        &[KeyCode::Tab, KeyCode::Down, KeyCode::Down, KeyCode::Down],
    );
    app.on_key(key(KeyCode::Enter));
    type_text(&mut app, ", 0.3");
    app.on_key(key(KeyCode::Enter));
    assert!(app.edited());
    assert_eq!(
        app.entries().len(),
        8,
        "the results stay until the next run"
    );
    let before: Vec<(String, Option<f64>)> = app
        .entries()
        .iter()
        .map(|e| {
            (
                e.design.id.clone(),
                e.row.as_ref().and_then(|r| r.max_shear_deg),
            )
        })
        .collect();
    match app.on_key(key(KeyCode::Char('r'))) {
        Command::Start {
            plan, dir, resume, ..
        } => {
            assert_eq!(plan.len(), 16);
            // A design is its values: the grown grid resumes in the same folder, and the store
            // keeps the eight finished rows (renumbered) and runs the eight new designs.
            assert_eq!(dir, PathBuf::from("/session/run-1"));
            assert!(resume);
        }
        other => panic!("expected a start, got {other:?}"),
    }
    assert_eq!(app.entries().len(), 16);
    assert_eq!(app.counts().0, 8, "the finished rows stay on the table");
    // Each kept row sits on the design with its values (the id's hash part), renumbered.
    for (old_id, shear) in before {
        let hash = old_id.split('-').nth(1).unwrap();
        let e = app
            .entries()
            .iter()
            .find(|e| e.design.id.ends_with(hash))
            .unwrap();
        let row = e.row.as_ref().unwrap();
        assert_eq!(row.design, e.design.id);
        assert_eq!(row.max_shear_deg, shear);
    }
}

#[test]
fn sorting_and_the_feasible_filter() {
    let mut app = explorer(false);
    finished_run(&mut app);
    // From #, one press sorts by the shear (it took six, through every parameter).
    press(&mut app, &[KeyCode::Char('s'); 1]);
    assert_eq!(app.sort_name(app.sort().column), "shear");
    let order: Vec<usize> = app
        .visible()
        .iter()
        .map(|&i| app.entries()[i].design.index)
        .collect();
    let shear = |i: usize| FIGURES[i].0;
    assert!(
        order.windows(2).all(|w| shear(w[0]) <= shear(w[1])),
        "{order:?}"
    );
    assert_eq!(order[0], 7, "the open design has the least shear");
    app.on_key(key(KeyCode::Char('S')));
    assert_eq!(app.entries()[app.visible()[0]].design.index, 0);
    app.on_key(key(KeyCode::Char('f')));
    let feasible: Vec<usize> = app
        .visible()
        .iter()
        .map(|&i| app.entries()[i].design.index)
        .collect();
    assert_eq!(feasible, [7]);
    // After shear: tension, force, verdict, time, then the five parameters, then round to the
    // design number.
    press(&mut app, &[KeyCode::Char('s'); 4]);
    assert_eq!(app.sort_name(app.sort().column), "time");
    press(&mut app, &[KeyCode::Char('s'); 1]);
    assert_eq!(app.sort_name(app.sort().column), "r");
    press(&mut app, &[KeyCode::Char('s'); 5]);
    assert_eq!(app.sort().column, 0);
}

#[test]
fn detail_help_export_and_quit() {
    let mut app = explorer(false);
    // Nothing to export before a run.
    assert_eq!(app.on_key(key(KeyCode::Char('e'))), Command::None);
    assert!(app.status().contains("nothing to export"));
    finished_run(&mut app);
    app.on_key(key(KeyCode::Down));
    app.on_key(key(KeyCode::Enter));
    assert_eq!(*app.mode(), Mode::Detail);
    assert_eq!(app.selected_entry().unwrap().design.index, 1);
    app.on_key(key(KeyCode::Down));
    assert_eq!(app.selected_entry().unwrap().design.index, 2);
    app.on_key(key(KeyCode::Esc));
    assert_eq!(*app.mode(), Mode::Normal);
    app.on_key(key(KeyCode::Char('?')));
    assert_eq!(*app.mode(), Mode::Help);
    app.on_key(key(KeyCode::Char('x')));
    assert_eq!(*app.mode(), Mode::Normal);
    app.on_key(key(KeyCode::Char('e')));
    let Mode::Exporting { buffer } = app.mode().clone() else {
        panic!("expected the export prompt, got {:?}", app.mode())
    };
    assert_eq!(buffer, "paper-box-explorer-export");
    type_text(&mut app, "-a");
    assert_eq!(
        app.on_key(key(KeyCode::Enter)),
        Command::Export {
            from: vec![PathBuf::from("/session/run-1")],
            to: PathBuf::from("paper-box-explorer-export-a"),
        }
    );
    app.on_message(Message::Exported(Ok(vec![PathBuf::from("x/report.png")])));
    assert!(app.status().contains("report.png"), "{}", app.status());
    assert_eq!(app.on_key(key(KeyCode::Char('q'))), Command::Quit);
    let ctrl_c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
    assert_eq!(app.on_key(ctrl_c), Command::Quit);
}

#[test]
fn invalid_and_failed_designs_show_their_reason() {
    let mut app = explorer(false);
    app.on_key(key(KeyCode::Char('r')));
    let mut bad = row(&app, 3, FIGURES[3]);
    bad.verdict = wovenform::verdict::Verdict::Failed;
    bad.converged = false;
    bad.failure = Some("the step from load 0.9100 could not converge".into());
    app.on_message(Message::Row(Box::new(bad)));
    press(
        &mut app,
        &[KeyCode::Down, KeyCode::Down, KeyCode::Down, KeyCode::Enter],
    );
    let s = screen(&app, 80, 24);
    assert!(s.contains("! failed"), "{s}");
    assert!(s.contains("could not converge"), "{s}");
}

#[test]
fn a_field_is_read_when_its_design_is_selected_and_drawing_reads_no_file() {
    let session = tempfile::tempdir().expect("a temporary folder");
    let params = Parameters::new(default_source()).expect("the default grid is valid");
    let mut app = App::new(params, session.path().to_path_buf(), false);
    app.on_key(key(KeyCode::Char('r')));
    app.on_message(Message::Started { to_run: 8, kept: 0 });
    let run = app
        .run_dir()
        .map(std::path::Path::to_path_buf)
        .expect("a run folder");
    std::fs::create_dir_all(run.join("fields")).expect("the fields folder");
    let locking = app.table_plan().base_scene.fabric.locking_angle_deg;
    let ids: Vec<String> = app.entries().iter().map(|e| e.design.id.clone()).collect();
    for i in [0, 7] {
        let field = corner_field(&ids[i], FIGURES[i].0, locking);
        let text = serde_json::to_string(&field).expect("a field is plain data");
        std::fs::write(run.join("fields").join(format!("{}.json", ids[i])), text)
            .expect("the field written");
    }
    // Design 7 finishes while design 0 is selected: its field waits until it is selected.
    let r = row(&app, 7, FIGURES[7]);
    app.on_message(Message::Row(Box::new(r)));
    assert!(app.field(&ids[7]).is_none());
    // The selected design finishes: its field is read then.
    let r = row(&app, 0, FIGURES[0]);
    app.on_message(Message::Row(Box::new(r)));
    assert!(matches!(app.field(&ids[0]), Some(Ok(_))));
    // Selecting design 7 reads its field.
    app.on_key(key(KeyCode::End));
    assert!(matches!(app.field(&ids[7]), Some(Ok(_))));
    // With the files gone, the detail still draws the map: drawing reads only the state.
    std::fs::remove_dir_all(run.join("fields")).expect("the fields removed");
    let s = screen(&app, 160, 48);
    assert!(s.contains("design 7 · r 10, rp 15, rm 10 mm"), "{s}");
    assert!(s.contains("shear, cell peak 58.0° at (30, 30) mm"), "{s}");
    assert!(!s.contains("no map"), "{s}");
}

#[test]
fn a_swept_locking_angle_is_each_designs_own_limit() {
    // Locking angles 55° and 65° swept over the open box: a design at 58° of shear is over the
    // first (✗ shear, in red) and within the second; the verdict's reason must use the design's
    // own limit, not the base scene's 60°.
    let dir = tempfile::tempdir().unwrap();
    let preset =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/paper-box-open.toml");
    let sweep = dir.path().join("locking.toml");
    std::fs::write(
        &sweep,
        format!(
            "base = {:?}\n[sweep]\nfabric.locking_angle_deg = [55.0, 65.0]\n",
            preset.display().to_string()
        ),
    )
    .unwrap();
    let source = wovenform::tui::source_of_file(&sweep).unwrap();
    let mut app = App::new(
        Parameters::new(source).unwrap(),
        PathBuf::from("/session"),
        false,
    );
    assert_eq!(app.entries().len(), 2);
    assert_eq!(app.entries()[0].limits.locking_angle_deg, 55.0);
    assert_eq!(app.entries()[1].limits.locking_angle_deg, 65.0);
    app.on_key(key(KeyCode::Char('r')));
    app.on_message(Message::Started { to_run: 2, kept: 0 });
    // 58° and 300 N: over 55° (and under the 60° of the base scene), within 65°.
    let mut over = row(&app, 0, (58.0, 300.0, 6000.0, 1.0));
    over.verdict = wovenform::verdict::Verdict::Infeasible;
    over.feasible = false;
    over.map = None;
    let mut within = row(&app, 1, (58.0, 300.0, 6000.0, 1.0));
    within.map = None;
    app.on_message(Message::Row(Box::new(over)));
    app.on_message(Message::Row(Box::new(within)));
    let s = screen(&app, 120, 30);
    assert!(s.contains("✗ shear"), "{s}");
    assert!(!s.contains("✗ tension"), "{s}");
    assert!(s.contains("✓ feasible"), "{s}");
}

#[test]
fn m_re_runs_only_the_marginal_designs_one_level_finer() {
    let mut app = explorer(false);
    // Nothing marginal yet: m says so and starts nothing.
    assert!(matches!(app.on_key(key(KeyCode::Char('m'))), Command::None));
    assert!(
        app.status().contains("no marginal design"),
        "{}",
        app.status()
    );
    finished_run(&mut app);
    // Design 7 at 59.5° ± 1.8° (standard): the 60° locking angle is inside its band.
    let mut r = row(&app, 7, (59.5, 297.0, 6507.0, 1.5));
    assert_eq!(r.verdict, wovenform::verdict::Verdict::Marginal);
    r.map = None;
    app.on_message(Message::Row(Box::new(r)));
    let s = screen(&app, 80, 24);
    assert!(s.contains("1 marginal: m re-runs them"), "{s}");
    match app.on_key(key(KeyCode::Char('m'))) {
        Command::Start {
            plan, resume, only, ..
        } => {
            let only = only.expect("only the marginal designs");
            assert_eq!(only.len(), 1);
            assert!(only.contains(&app.entries()[7].design.id));
            assert!(!resume);
            // One level finer than standard: fine, 1.25 mm elements.
            assert_eq!(plan.base_scene.mesh.element_size, 1.25);
        }
        other => panic!("expected a start, got {other:?}"),
    }
    assert!(
        app.entries()[7].row.is_none(),
        "its row waits for the finer run"
    );
    assert!(
        app.entries()[0].row.is_some(),
        "the settled designs keep theirs"
    );
}

#[test]
fn a_new_locking_angle_judges_the_rows_again_without_running() {
    let mut app = explorer(false);
    finished_run(&mut app);
    let verdict = |app: &App, i: usize| {
        app.entries()[i]
            .row
            .as_ref()
            .map(|r| r.verdict.word().to_string())
    };
    assert_eq!(verdict(&app, 0).as_deref(), Some("INFEASIBLE"));
    // r, rp, rm, friction, holder, then the locking angle.
    press(&mut app, &[KeyCode::Tab]);
    press(&mut app, &[KeyCode::Down; 5]);
    app.on_key(key(KeyCode::Enter));
    for _ in 0..4 {
        app.on_key(key(KeyCode::Backspace));
    }
    type_text(&mut app, "80");
    app.on_key(key(KeyCode::Enter));
    // Design 0 at 78.0° ± 1.2°: under 80° by more than its error. Nothing to run again.
    assert!(!app.edited(), "the table is the edited grid");
    assert_eq!(verdict(&app, 0).as_deref(), Some("FEASIBLE"));
    assert_eq!(app.entries()[0].limits.locking_angle_deg, 80.0);
    assert!(app.status().contains("judged again"), "{}", app.status());
    // Design 7 at 58.0°: with the locking angle at 58.5° it lies inside the band.
    app.on_key(key(KeyCode::Enter));
    for _ in 0..4 {
        app.on_key(key(KeyCode::Backspace));
    }
    type_text(&mut app, "58.5");
    app.on_key(key(KeyCode::Enter));
    assert_eq!(verdict(&app, 7).as_deref(), Some("MARGINAL"));
    assert_eq!(verdict(&app, 0).as_deref(), Some("INFEASIBLE"));
}

#[test]
fn exports_stay_out_of_repositories_and_old_sessions_are_pruned() {
    let dir = tempfile::tempdir().unwrap();
    // Not in a repository: the working folder.
    assert_eq!(wovenform::tui::export_home(dir.path()), PathBuf::new());
    // In (or below) one: ~/wovenform.
    std::fs::create_dir_all(dir.path().join("repo/.git")).unwrap();
    std::fs::create_dir_all(dir.path().join("repo/sub")).unwrap();
    if let Some(home) = std::env::var_os("HOME") {
        assert_eq!(
            wovenform::tui::export_home(&dir.path().join("repo/sub")),
            PathBuf::from(home).join("wovenform")
        );
    }
    // Sessions: the one left 8 days ago goes, today's and other folders stay.
    let old = dir.path().join("wovenform-explorer-old");
    let new = dir.path().join("wovenform-explorer-new");
    std::fs::create_dir_all(old.join("run-1")).unwrap();
    std::fs::create_dir_all(&new).unwrap();
    let eight_days = std::time::Duration::from_secs(8 * 86_400);
    std::fs::File::open(&old)
        .unwrap()
        .set_modified(std::time::SystemTime::now() - eight_days)
        .unwrap();
    assert_eq!(wovenform::tui::prune_sessions(dir.path(), 7), 1);
    assert!(!old.exists() && new.exists() && dir.path().join("repo").exists());
}

/// A fabric that bends has a wrinkle column after the force, sorted as the last figure; the
/// paper's membrane has none (`sorting_and_the_feasible_filter`: from time straight to r).
#[test]
fn a_bending_fabric_adds_a_wrinkle_column_to_the_table_and_the_sort() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("presets/box-holder-window.toml");
    let doc: toml::Table = std::fs::read_to_string(&path).unwrap().parse().unwrap();
    let source = wovenform::tui::params::Source {
        path,
        title: "holder window".into(),
        doc,
        embedded: false,
    };
    let mut app = App::new(
        Parameters::new(source).unwrap(),
        PathBuf::from("/session"),
        false,
    );
    let header = screen(&app, 200, 30)
        .lines()
        .find(|l| l.contains("shear°"))
        .unwrap()
        .to_string();
    let at = |name: &str| {
        header
            .find(name)
            .unwrap_or_else(|| panic!("{name}: {header}"))
    };
    assert!(
        at("F kN") < at("wr mm") && at("wr mm") < at("verdict"),
        "{header}"
    );
    press(&mut app, &[KeyCode::Char('s'); 5]);
    assert_eq!(app.sort_name(app.sort().column), "time");
    press(&mut app, &[KeyCode::Char('s'); 1]);
    assert_eq!(app.sort_name(app.sort().column), "wrinkles");
    press(&mut app, &[KeyCode::Char('s'); 1]);
    assert_eq!(app.sort_name(app.sort().column), "r");
    let plain = screen(&explorer(false), 200, 30);
    assert!(!plain.contains("wr mm"), "{plain}");
}
