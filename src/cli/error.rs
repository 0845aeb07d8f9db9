//! The command line's one error: a message for stderr and the exit code it ends with (after
//! cargo's `CliError`).

use wovenform::publish::PublishError;
use wovenform::report::error::DrawError;
use wovenform::scene::SceneError;
use wovenform::study::sweep::{StoreError, SweepError};

/// Why a command did not succeed, and its exit code: 2 bad input, 1 a failed run.
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
pub struct CliError {
    pub message: String,
    pub exit_code: u8,
}

impl CliError {
    /// Bad input (exit code 2): the message names the file or option and what was expected.
    pub fn bad_input(message: impl Into<String>) -> CliError {
        CliError {
            message: message.into(),
            exit_code: 2,
        }
    }

    /// A failed run (exit code 1).
    pub fn failed(message: impl Into<String>) -> CliError {
        CliError {
            message: message.into(),
            exit_code: 1,
        }
    }
}

impl From<SweepError> for CliError {
    fn from(e: SweepError) -> CliError {
        if e.is_bad_input() {
            CliError::bad_input(e.to_string())
        } else {
            CliError::failed(e.to_string())
        }
    }
}

impl From<SceneError> for CliError {
    fn from(e: SceneError) -> CliError {
        CliError::bad_input(e.to_string())
    }
}

impl From<StoreError> for CliError {
    fn from(e: StoreError) -> CliError {
        CliError::failed(e.to_string())
    }
}

impl From<PublishError> for CliError {
    fn from(e: PublishError) -> CliError {
        CliError::failed(e.to_string())
    }
}

impl From<DrawError> for CliError {
    fn from(e: DrawError) -> CliError {
        CliError::failed(e.to_string())
    }
}
