//! The terminal explorer: its state driven by keys, its screens drawn on a test backend, and
//! the real binary in a pseudo-terminal.
//!
//! One test binary for the group (linking one binary instead of one per file): each file
//! below is a module, the helpers they share are the modules at the top.

#[path = "../analytic/mod.rs"]
mod analytic;
#[path = "../common/mod.rs"]
mod common;
#[path = "../tui_common/mod.rs"]
mod tui_common;

mod tui_detail;
mod tui_frontier;
mod tui_keys;
mod tui_pty;
mod tui_screens;
