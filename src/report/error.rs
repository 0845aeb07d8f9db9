//! Why a picture could not be drawn.

use std::path::PathBuf;

/// A picture (`what`: chart, map, sheet) that could not be drawn to its file.
#[derive(Debug, thiserror::Error)]
#[error("{}: cannot draw the {what}: {message}", path.display())]
pub struct DrawError {
    pub path: PathBuf,
    pub what: &'static str,
    /// What the plotting library said.
    pub message: String,
}

impl DrawError {
    /// The error maker for the picture `what` at `path`.
    pub fn at(
        path: &std::path::Path,
        what: &'static str,
    ) -> impl Fn(&dyn std::fmt::Display) -> DrawError {
        let path = path.to_path_buf();
        move |e| DrawError {
            path: path.clone(),
            what,
            message: e.to_string(),
        }
    }
}

/// The error of the bitmap the pictures are drawn on (plotters' bitmap backend).
pub type CanvasError =
    <plotters::prelude::BitMapBackend<'static> as plotters::prelude::DrawingBackend>::ErrorType;

/// What the plotting library said when a shape, a text or a chart could not be drawn on the
/// canvas (its message as it gives it).
#[derive(Debug, thiserror::Error)]
#[error(transparent)]
pub struct PlotError(#[from] plotters::drawing::DrawingAreaErrorKind<CanvasError>);
