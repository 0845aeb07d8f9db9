//! What can go wrong in the explorer, by kind: a parameter as typed, the work off the
//! interface thread, a design's field, the terminal.

use std::path::PathBuf;

use crate::publish::PublishError;
use crate::study::sweep::{StoreError, SweepError};

/// What is wrong with a parameter as typed, or with the plan the parameters make. Shown under
/// the field while the user types.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// The text is not what the field takes; the message says what was expected.
    #[error("{0}")]
    Text(String),
    /// The base scene refuses the value: its message, which names the key.
    #[error("{0}")]
    Scene(String),
    /// The sweep document with these parameters makes no plan.
    #[error("{0}")]
    Plan(String),
}

/// Why an export or a design's own files could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WorkError {
    #[error(transparent)]
    Sweep(#[from] SweepError),
    #[error(transparent)]
    Publish(#[from] PublishError),
}

/// Why a finished design's field is not there to draw.
#[derive(Debug, thiserror::Error)]
pub enum FieldError {
    /// The explorer has not run anything yet.
    #[error("no run folder")]
    NoRunFolder,
    #[error(transparent)]
    Store(#[from] StoreError),
}

/// Why the explorer could not start or go on: its sweep file, the terminal.
#[derive(Debug, thiserror::Error)]
pub enum TuiError {
    #[error("{}: cannot read the sweep file: {source}", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: not valid TOML: {message}", path.display())]
    Toml { path: PathBuf, message: String },
    /// Raw mode or the alternate screen refused.
    #[error("cannot take the terminal: {0}")]
    Terminal(std::io::Error),
    #[error("cannot draw on the terminal: {0}")]
    Draw(std::io::Error),
    /// Reading the keys failed.
    #[error("{0}")]
    Events(std::io::Error),
    /// Ended from outside by a signal (SIGTERM, SIGHUP, SIGINT), the terminal restored.
    #[error("ended by signal {0} (the terminal is restored; the finished rows are kept)")]
    Signal(i32),
}
