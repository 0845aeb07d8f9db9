//! The command line as scripts and people run it: each command's outputs, its refusals of
//! bad input, and what it never overwrites or loses.
//!
//! One test binary for the group (linking one binary instead of one per file): each file
//! below is a module, the helpers they share are the modules at the top.

#[path = "../analytic/mod.rs"]
mod analytic;
#[path = "../common/mod.rs"]
mod common;
#[path = "../slurm_common/mod.rs"]
mod slurm_common;

mod cantilever_cli;
mod cli;
mod converge_cli;
mod frontier_cli;
mod hostile;
mod hostile_values;
mod mesh_hostile_cli;
mod mesh_scene_cli;
mod newton_trace_cli;
mod output_folders;
mod run_cli;
mod scene_errors;
mod slurm_cli;
mod slurm_hostile;
mod stl_hostile;
mod sweep_announce;
mod sweep_cli;
mod tools_cli;
