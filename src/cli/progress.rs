//! Progress bars on stderr (drawn only when stderr is a terminal).

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar of `len` on stderr in the indicatif `template`; hidden when stderr is not a
/// terminal.
pub fn stderr_bar(len: u64, template: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}

/// A progress bar of the punch stroke.
pub fn stroke_bar(stroke_mm: f64) -> ProgressBar {
    let bar = stderr_bar(1000, "{spinner} [{elapsed_precise}] {bar:40} {msg}");
    if bar.is_hidden() {
        return bar;
    }
    bar.set_message(format!("stroke 0.00 of {stroke_mm} mm"));
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

/// Shows `fraction` of a stroke of `stroke_mm` on a [`stroke_bar`].
pub fn show_stroke(bar: &ProgressBar, fraction: f64, stroke_mm: f64) {
    bar.set_position((fraction * 1000.0).round() as u64);
    bar.set_message(format!(
        "stroke {:.2} of {stroke_mm} mm",
        fraction * stroke_mm
    ));
}
