//! The terminal explorer (ratatui + crossterm): edit the sweep's parameters, run it on worker
//! threads (the headless sweep engine), watch the results table fill, inspect a design's shear
//! map, export the report.
//!
//! `app` holds the state and the keys, `view` draws it (the explorer is a widget, `&App`;
//! `detail` draws a design's detail), `worker` runs sweeps and exports off the interface
//! thread, `params` checks and turns the edited parameters into a plan.

pub mod app;
mod detail;
pub mod error;
pub mod frontier;
mod keys;
pub mod params;
mod runs;
pub mod shear_map;
mod signals;
mod style;
pub mod view;
pub mod worker;

use std::io::{self, Stdout};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;
use ratatui::crossterm::cursor::Show;
use ratatui::crossterm::event::{self, Event, KeyEventKind};
use ratatui::crossterm::execute;
use ratatui::crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};

use app::{App, Command};
use error::TuiError;
use params::{Parameters, Source};

/// Whether the terminal shows colours: not with `NO_COLOR` set or `TERM=dumb`.
pub fn colour_wanted() -> bool {
    std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
        && std::env::var("TERM").map_or(true, |t| t != "dumb")
}

/// The sweep document of a sweep file.
pub fn source_of_file(path: &std::path::Path) -> Result<Source, TuiError> {
    let text = crate::files::read_text(path, crate::files::MAX_TEXT_BYTES).map_err(|source| {
        TuiError::Read {
            path: path.to_path_buf(),
            source,
        }
    })?;
    let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| TuiError::Toml {
        path: path.to_path_buf(),
        message: e.to_string().trim_end().to_string(),
    })?;
    Ok(Source {
        path: path.to_path_buf(),
        title: path.display().to_string(),
        doc,
        embedded: false,
    })
}

fn restore() {
    let _ = disable_raw_mode();
    let _ = execute!(io::stdout(), LeaveAlternateScreen, Show);
}

/// Restores the terminal on a panic of the interface thread (a panic on a worker is caught
/// by the sweep and becomes a FAILED row; its message would only garble the screen).
fn install_panic_hook() {
    let ui = std::thread::current().id();
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if std::thread::current().id() == ui {
            restore();
            previous(info);
        }
    }));
}

/// Opens the explorer on a sweep document and runs it until the user quits. The runs are
/// written under `session` (a folder per run), so that nothing is lost on a crash.
pub fn explore(params: Parameters, session: PathBuf) -> Result<(), TuiError> {
    let mut app = App::new(params, session.clone(), colour_wanted());
    app.export_dir =
        export_home(&std::env::current_dir().unwrap_or_default()).join(&app.export_dir);
    enable_raw_mode().map_err(TuiError::Terminal)?;
    if let Err(e) = execute!(io::stdout(), EnterAlternateScreen) {
        restore();
        return Err(TuiError::Terminal(e));
    }
    install_panic_hook();
    signals::install();
    let outcome = Terminal::new(CrosstermBackend::new(io::stdout()))
        .map_err(TuiError::Draw)
        .and_then(|mut terminal| event_loop(&mut terminal, &mut app));
    restore();
    if app.runs > 0 {
        let runs: Vec<String> = (1..=app.runs)
            .map(|k| session.join(format!("run-{k}")))
            .filter(|d| d.join("results.csv").exists())
            .map(|d| d.display().to_string())
            .collect();
        eprintln!(
            "wovenform explorer: the rows of this session are kept in {} (each a sweep folder: \
             `wovenform merge {} --out OUT` exports the last)",
            runs.join(", "),
            runs.last().map_or("RUN", |s| s.as_str())
        );
    } else {
        // Nothing was run: leave no empty session folder behind (it is removed only if empty).
        let _ = std::fs::remove_dir(&session);
    }
    match signals::received() {
        Some(signal) => Err(TuiError::Signal(signal)),
        None => outcome,
    }
}

fn event_loop(
    terminal: &mut Terminal<CrosstermBackend<Stdout>>,
    app: &mut App,
) -> Result<(), TuiError> {
    let opened = Instant::now();
    let (tx, rx) = mpsc::channel();
    let mut stop: Option<Arc<AtomicBool>> = None;
    loop {
        app.set_now(opened.elapsed().as_secs_f64());
        app.note_status_time();
        while let Ok(m) = rx.try_recv() {
            app.on_message(m);
        }
        if signals::received().is_some() {
            stop_worker(&stop);
            return Ok(());
        }
        terminal
            .draw(|f| f.render_widget(&*app, f.area()))
            .map_err(TuiError::Draw)?;
        // A signal interrupts the wait: the loop's next turn sees it.
        match event::poll(Duration::from_millis(100)) {
            Ok(true) => {}
            Ok(false) => continue,
            Err(_) if signals::received().is_some() => continue,
            Err(e) => return Err(TuiError::Events(e)),
        }
        let Event::Key(key) = event::read().map_err(TuiError::Events)? else {
            continue;
        };
        if key.kind != KeyEventKind::Press {
            continue;
        }
        match app.on_key(key) {
            Command::None => {}
            Command::Quit => {
                stop_worker(&stop);
                return Ok(());
            }
            Command::Cancel => stop_worker(&stop),
            Command::Start {
                plan,
                dir,
                resume,
                only,
            } => {
                stop = Some(worker::start_sweep(*plan, dir, resume, only, tx.clone()));
            }
            Command::Frontier {
                lattice,
                dir,
                resume,
            } => {
                stop = Some(worker::start_frontier(*lattice, dir, resume, tx.clone()));
            }
            Command::Export { from, to } => worker::start_export(from, to, tx.clone()),
            Command::WriteFiles { design, scene, dir } => {
                worker::start_design_files(design, *scene, dir, tx.clone())
            }
        }
    }
}

/// Asks the running sweep or frontier, if any, to stop (its finished rows are kept).
fn stop_worker(stop: &Option<Arc<AtomicBool>>) {
    if let Some(s) = stop {
        s.store(true, Ordering::Relaxed);
    }
}

/// Where exports go by default: the working folder, unless it lies inside a repository (a
/// `.git` in it or above it), where results do not belong: then `~/wovenform`.
pub fn export_home(cwd: &std::path::Path) -> PathBuf {
    let in_repository = cwd.ancestors().any(|a| a.join(".git").exists());
    match std::env::var_os("HOME") {
        Some(home) if in_repository => PathBuf::from(home).join("wovenform"),
        _ => PathBuf::new(),
    }
}

/// Removes the explorer's session folders in `temp` left more than `days` ago (each kept its
/// runs for a crash); returns how many went.
pub fn prune_sessions(temp: &std::path::Path, days: u64) -> usize {
    let Ok(entries) = std::fs::read_dir(temp) else {
        return 0;
    };
    let old = std::time::Duration::from_secs(days * 86_400);
    entries
        .flatten()
        .filter(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with("wovenform-explorer-")
        })
        .filter(|e| {
            e.metadata()
                .and_then(|m| m.modified())
                .ok()
                .and_then(|t| t.elapsed().ok())
                .is_some_and(|age| age > old)
        })
        .filter(|e| std::fs::remove_dir_all(e.path()).is_ok())
        .count()
}

#[cfg(test)]
mod tests {
    use super::params::default_source;
    use super::*;

    /// What the loop does on every tick (the clock, then the status's time noted) and what the
    /// status line shows.
    #[test]
    fn a_status_message_fades_and_a_new_one_shows_at_once() {
        let params = Parameters::new(default_source()).unwrap();
        let mut app = App::new(params, "/session".into(), false);
        app.status = "exported to /tmp/x".into();
        assert_eq!(app.fresh_status(), Some("exported to /tmp/x"));
        app.note_status_time();
        app.set_now(5.0);
        assert!(app.fresh_status().is_some(), "still news after 5 s");
        app.set_now(30.0);
        assert_eq!(app.fresh_status(), None, "stale after 30 s");
        app.status = "cancelling…".into();
        assert_eq!(app.fresh_status(), Some("cancelling…"));
    }
}
