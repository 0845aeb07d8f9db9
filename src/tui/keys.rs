//! The explorer's keys: what each one changes in the state and which command it asks of the
//! event loop.

use std::path::PathBuf;

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use super::app::{App, Command, DetailMap, Focus, Mode, RunState};
use super::params::Target;

impl App {
    /// What a key does.
    pub fn on_key(&mut self, key: KeyEvent) -> Command {
        let command = self.apply_key(key);
        self.load_selected_field();
        command
    }

    fn apply_key(&mut self, key: KeyEvent) -> Command {
        if key.modifiers.contains(KeyModifiers::CONTROL) && key.code == KeyCode::Char('c') {
            return Command::Quit;
        }
        match self.mode.clone() {
            Mode::Help => {
                if key.code == KeyCode::Char('q') {
                    return Command::Quit;
                }
                self.mode = Mode::Normal;
                Command::None
            }
            Mode::Editing { buffer, .. } => self.on_editing_key(key, buffer),
            Mode::Exporting { buffer } => self.on_exporting_key(key, buffer),
            Mode::Detail => {
                match key.code {
                    KeyCode::Char('q') => return Command::Quit,
                    KeyCode::Up | KeyCode::Char('k') => self.move_selection(-1),
                    KeyCode::Down | KeyCode::Char('j') => self.move_selection(1),
                    KeyCode::Char('?') => self.mode = Mode::Help,
                    KeyCode::Char('t') => {
                        self.detail_map = self.detail_map.toggled(DetailMap::Tension)
                    }
                    KeyCode::Char('z') => {
                        self.detail_map = self.detail_map.toggled(DetailMap::Wrinkles)
                    }
                    KeyCode::Char('+') => return self.rerun_selected(),
                    KeyCode::Char('w') => return self.write_selected_files(),
                    _ => self.mode = Mode::Normal,
                }
                Command::None
            }
            Mode::Normal => self.on_normal_key(key),
        }
    }

    /// A key while a parameter is edited: the text typed so far is `buffer`.
    fn on_editing_key(&mut self, key: KeyEvent, mut buffer: String) -> Command {
        match key.code {
            KeyCode::Esc => {
                self.mode = Mode::Normal;
                return Command::None;
            }
            KeyCode::Enter => {
                match self.params.commit(self.cursor, &buffer) {
                    Ok(()) => {
                        self.mode = Mode::Normal;
                        self.follow_edits();
                    }
                    Err(e) => {
                        self.mode = Mode::Editing {
                            buffer,
                            error: Some(e),
                        }
                    }
                }
                return Command::None;
            }
            KeyCode::Backspace => {
                buffer.pop();
            }
            KeyCode::Char(c) => buffer.push(c),
            _ => return Command::None,
        }
        let error = self.params.check(self.cursor, &buffer).err();
        self.mode = Mode::Editing { buffer, error };
        Command::None
    }

    /// A key while the export folder is asked for: the text typed so far is `buffer`.
    fn on_exporting_key(&mut self, key: KeyEvent, mut buffer: String) -> Command {
        match key.code {
            KeyCode::Esc => self.mode = Mode::Normal,
            KeyCode::Enter => {
                self.mode = Mode::Normal;
                return self.export_to(&buffer);
            }
            KeyCode::Backspace => {
                buffer.pop();
                self.mode = Mode::Exporting { buffer };
            }
            KeyCode::Char(c) => {
                buffer.push(c);
                self.mode = Mode::Exporting { buffer };
            }
            _ => {}
        }
        Command::None
    }

    /// The export into the folder typed, unless it is empty or holds results already.
    fn export_to(&mut self, typed: &str) -> Command {
        let to = PathBuf::from(typed.trim());
        if typed.trim().is_empty() {
            self.status = "export: expected a folder".into();
            return Command::None;
        }
        if to.join("results.csv").exists() {
            self.status = format!(
                "export: {} already holds results; choose another folder",
                to.display()
            );
            return Command::None;
        }
        let from = self.row_dirs();
        if from.is_empty() {
            return Command::None;
        }
        self.export_dir = to.clone();
        self.status = format!("exporting to {} …", to.display());
        Command::Export { from, to }
    }

    fn on_normal_key(&mut self, key: KeyEvent) -> Command {
        match key.code {
            KeyCode::Char('q') => return Command::Quit,
            KeyCode::Char('?') => self.mode = Mode::Help,
            KeyCode::Tab | KeyCode::BackTab => {
                self.focus = match self.focus {
                    Focus::Parameters => Focus::Results,
                    Focus::Results => Focus::Parameters,
                }
            }
            KeyCode::Char('r') => return self.start(),
            KeyCode::Char('m') => return self.rerun_marginal(),
            KeyCode::Char('b') => return self.find_boundary(),
            KeyCode::Char('t') => self.detail_map = self.detail_map.toggled(DetailMap::Tension),
            KeyCode::Char('z') => self.detail_map = self.detail_map.toggled(DetailMap::Wrinkles),
            KeyCode::Char('+') if self.focus == Focus::Results => return self.rerun_selected(),
            KeyCode::Char('w') if self.focus == Focus::Results => {
                return self.write_selected_files();
            }
            KeyCode::Char('c') | KeyCode::Esc if self.run == RunState::Running => {
                self.run = RunState::Stopping;
                self.status =
                    "cancelling: the designs on the workers stop at their next load step".into();
                return Command::Cancel;
            }
            KeyCode::Char('e') => {
                if self.entries.iter().any(|e| e.row.is_some()) && self.run_dir.is_some() {
                    self.mode = Mode::Exporting {
                        buffer: self.free_export_dir().display().to_string(),
                    };
                } else {
                    self.status = "nothing to export yet: r runs the sweep".into();
                }
            }
            KeyCode::Char('s') => {
                self.sort.column = self.next_sort_column(self.sort.column);
                self.sort.descending = false;
            }
            KeyCode::Char('S') => self.sort.descending = !self.sort.descending,
            KeyCode::Char('f') => {
                self.feasible_only = !self.feasible_only;
                self.selected = 0;
            }
            KeyCode::Up | KeyCode::Char('k') => self.move_selection(-1),
            KeyCode::Down | KeyCode::Char('j') => self.move_selection(1),
            KeyCode::PageUp => self.move_selection(-10),
            KeyCode::PageDown => self.move_selection(10),
            KeyCode::Home | KeyCode::Char('g') => self.move_selection(-1_000_000),
            KeyCode::End | KeyCode::Char('G') => self.move_selection(1_000_000),
            KeyCode::Left | KeyCode::Right
                if self.focus == Focus::Parameters
                    && self.params.fields[self.cursor].target == Target::Accuracy =>
            {
                self.params.step_accuracy(key.code == KeyCode::Right);
                self.follow_edits();
            }
            KeyCode::Enter => match self.focus {
                Focus::Parameters => {
                    self.mode = Mode::Editing {
                        buffer: self.params.fields[self.cursor].text.clone(),
                        error: None,
                    }
                }
                Focus::Results => {
                    if self.selected_entry().is_some() {
                        self.mode = Mode::Detail;
                    }
                }
            },
            _ => {}
        }
        Command::None
    }
}
