//! Shared by the explorer's tests: an explorer on the default grid, results for its designs
//! and a synthetic shear field, drawn on a `TestBackend`.
#![allow(dead_code)]

use std::path::PathBuf;

use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use wovenform::study::sweep::{Row, StoredField};
use wovenform::tui::app::App;
use wovenform::tui::params::{Parameters, default_source};
use wovenform::tui::worker::Message;
use wovenform::verdict::Verdict;

/// Figures of the default grid's designs (r, rp, rm over the paper's tight and open radii,
/// μ 0.2, 1 MPa): max shear °, max tension N, punch force N, wall s. A real run at `standard`
/// gave them with an earlier solver; today's differ by up to 1.1° of shear and 63 N
/// of tension (the snapshots are drawn from these). Their verdicts are the paper's and
/// today's: the real drawings are checked in `figure11_box.rs` and, through the explorer, in
/// `tui_pty.rs`.
pub const FIGURES: [(f64, f64, f64, f64); 8] = [
    (78.0, 527.0, 7467.7, 4.2),
    (74.1, 481.0, 6580.0, 20.2),
    (71.4, 368.0, 7410.0, 3.1),
    (62.1, 253.0, 6360.0, 6.2),
    (73.8, 492.0, 7570.0, 4.6),
    (70.2, 474.0, 6750.0, 4.7),
    (65.4, 348.0, 7440.0, 3.9),
    (58.0, 297.0, 6507.0, 1.5),
];

/// An explorer on the embedded default, colours as asked.
pub fn explorer(colour: bool) -> App {
    let params = Parameters::new(default_source()).expect("the default grid is valid");
    App::new(params, PathBuf::from("/session"), colour)
}

pub fn key(code: KeyCode) -> KeyEvent {
    KeyEvent::new(code, KeyModifiers::NONE)
}

pub fn press(app: &mut App, codes: &[KeyCode]) {
    for c in codes {
        app.on_key(key(*c));
    }
}

pub fn type_text(app: &mut App, text: &str) {
    for ch in text.chars() {
        app.on_key(key(KeyCode::Char(ch)));
    }
}

/// The row of design `index` with the given figures; the verdict by the definition
/// (`analytic::verdict_word`): the shear and tension with the accuracy level's error bands
/// against the locking angle and the break tension. (A crate that uses this module declares `mod analytic;` too.)
pub fn row(app: &App, index: usize, figures: (f64, f64, f64, f64)) -> Row {
    let e = &app.entries()[index];
    let fabric = &app.table_plan().base_scene.fabric;
    let (shear, tension, force, wall) = figures;
    let err = app.params().accuracy.error();
    let word = crate::analytic::verdict_word(
        (shear, err.max_shear_deg, fabric.locking_angle_deg),
        (tension, err.max_tension_pct, fabric.break_tension_n),
    );
    let feasible = word == "FEASIBLE";
    Row {
        max_shear_deg: Some(shear),
        max_tension_n: Some(tension),
        punch_force_n: Some(force),
        max_shear_err_deg: Some(err.max_shear_deg),
        max_tension_err_pct: Some(err.max_tension_pct),
        punch_force_err_pct: Some(err.punch_force_pct),
        feasible,
        converged: true,
        wall_s: Some(wall),
        map: Some(format!("maps/{}.png", e.design.id)),
        ..Row::new(
            &e.design,
            e.params.clone(),
            Verdict::parse(word).expect("a verdict word"),
        )
    }
}

/// A quarter of a 170 mm blank in 5 mm elements whose shear peaks at `peak` over the punch
/// corner (30, 30) mm and falls off with the distance from it.
pub fn corner_field(id: &str, peak: f64, locking: f64) -> StoredField {
    let n = 17;
    let h = 5.0;
    let mut nodes = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            nodes.push([i as f64 * h, j as f64 * h]);
        }
    }
    let mut quads = Vec::new();
    let mut shear = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = (j * (n + 1) + i) as u32;
            quads.push([a, a + 1, a + n as u32 + 2, a + n as u32 + 1]);
            let c = [(i as f64 + 0.5) * h, (j as f64 + 0.5) * h];
            let d2 = (c[0] - 30.0).powi(2) + (c[1] - 30.0).powi(2);
            shear.push(peak * (-d2 / (2.0 * 12.0 * 12.0)).exp());
        }
    }
    StoredField {
        design: id.into(),
        verdict: String::new(),
        max_shear_deg: peak,
        locking_angle_deg: locking,
        subtitle: String::new(),
        quarter: true,
        nodes,
        quads,
        shear_deg: shear.clone(),
        max_at: Some([30.0, 30.0]),
        die_opening: Vec::new(),
        // Tension follows the shear (6 N per degree); equal elements, so the share over the
        // limit is the share of elements.
        tension_n: shear.iter().map(|s| 6.0 * s).collect(),
        break_tension_n: 1500.0,
        max_tension_n: 6.0 * peak,
        draw_in_mm: 12.5,
        area_over_limit_pct: 100.0 * shear.iter().filter(|s| **s > locking).count() as f64
            / shear.len() as f64,
        wrinkle_mm: Vec::new(),
        max_wrinkle_mm: None,
        wrinkle_limit_mm: 1.0,
    }
}

/// Delivers the rows of `designs` (and their fields) as the workers would.
pub fn deliver(app: &mut App, designs: &[usize]) {
    for &i in designs {
        let r = row(app, i, FIGURES[i]);
        let locking = app.table_plan().base_scene.fabric.locking_angle_deg;
        let id = r.design.clone();
        app.on_message(Message::Row(Box::new(r)));
        app.keep_field(id.clone(), corner_field(&id, FIGURES[i].0, locking));
    }
}

/// Runs the whole default grid as the workers would: `r`, every row, the end.
pub fn finished_run(app: &mut App) {
    app.on_key(key(KeyCode::Char('r')));
    app.on_message(Message::Started { to_run: 8, kept: 0 });
    deliver(app, &[0, 1, 2, 3, 4, 5, 6, 7]);
    app.on_message(Message::Finished {
        stopped: false,
        wall_s: 24.0,
        error: None,
    });
}

/// The screen as text: the explorer drawn as a widget over the whole terminal.
pub fn screen(app: &App, width: u16, height: u16) -> String {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("a test terminal");
    terminal
        .draw(|f| f.render_widget(app, f.area()))
        .expect("drawn");
    terminal.backend().to_string()
}

/// The screen's buffer, for looking at styles.
pub fn buffer(app: &App, width: u16, height: u16) -> ratatui::buffer::Buffer {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("a test terminal");
    terminal
        .draw(|f| f.render_widget(app, f.area()))
        .expect("drawn");
    terminal.backend().buffer().clone()
}
