//! Why a sweep's output folder could not be read or written, and writing a file of it whole:
//! shared by the folder's store and the stored fields.

use std::path::{Path, PathBuf};

/// Why the folder could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    #[error("{}: cannot {action}: {source}", path.display())]
    Io {
        path: PathBuf,
        action: &'static str,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: {source}", path.display())]
    NoLock {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: not a sweep lock file: {source}", path.display())]
    BadLock {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },
    #[error(
        "{}: the header has {problem}; expected the columns {expected} (the header was edited: restore it, or remove the folder to start again)",
        path.display()
    )]
    Header {
        path: PathBuf,
        /// What is wrong: the column found that a sweep does not write, or the one missing.
        problem: String,
        expected: String,
    },
    #[error("{}: {source}", path.display())]
    Field {
        path: PathBuf,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
}

impl StoreError {
    /// The error maker for a failed `action` ("write", "read", …) on `path`.
    pub fn io(path: &Path, action: &'static str) -> impl FnOnce(std::io::Error) -> StoreError {
        let path = path.to_path_buf();
        move |source| StoreError::Io {
            path,
            action,
            source,
        }
    }
}

/// Writes `text` to `path` through a temporary file in the same folder and a rename (never
/// half a file).
pub fn write_atomic(path: &Path, text: &str) -> Result<(), StoreError> {
    crate::files::write_atomic(path, text.as_bytes()).map_err(StoreError::io(path, "write"))
}
