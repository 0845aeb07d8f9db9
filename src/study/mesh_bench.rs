//! `wovenform bench --mesh`: what tools read from STL cost against the same tools given
//! analytically. Each preset's punch and die are tessellated to about 100 000 triangles each,
//! written as binary STL with a scene naming them, and the two runs are timed whole (for the
//! mesh scene: reading the files, checking them, building the distance and solving), the whole
//! blank both ways (a mesh scene's default), on one thread, medians of the repetitions.

use std::time::Instant;

use super::timing::{median, preset};
use crate::core::drawing::{DrawingFailure, DrawingProblem, DrawingResult, Symmetry};
use crate::core::tools::capped::tool_surfaces;
use crate::presets::{PAPER_BOX_OPEN, PAPER_BOX_TIGHT};
use crate::scene::SceneError;
use crate::stl::StlError;

/// About this many triangles per tool.
pub const TRIANGLES_PER_TOOL: f64 = 100_000.0;

/// One preset's comparison.
#[derive(Clone, Debug)]
pub struct MeshRun {
    pub name: &'static str,
    /// Triangles of the punch and the die, and the tessellation spacing of each, mm.
    pub triangles: [usize; 2],
    pub spacing_mm: [f64; 2],
    /// Median wall of the analytic run and of the mesh run (reading included), s.
    pub analytic_s: f64,
    pub mesh_s: f64,
    /// Of the mesh run: reading, checking and building the tools, s (median).
    pub read_s: f64,
    /// The mesh run against the analytic one: max shear (°), punch force (relative), draw-in
    /// (mm).
    pub departures: [f64; 3],
    /// Steps and Newton iterations, analytic then mesh.
    pub steps: [u32; 2],
    pub newton_iterations: [u32; 2],
}

/// Why a preset's comparison could not be made: its mesh scene could not be written or read,
/// or a run did not converge.
#[derive(Debug, thiserror::Error)]
pub enum MeshBenchError {
    /// The preset's text is not a TOML table.
    #[error("{0}")]
    PresetToml(toml::de::Error),
    /// The mesh scene cannot be written as TOML.
    #[error("{0}")]
    SceneToml(toml::ser::Error),
    #[error("{0}")]
    TempFolder(std::io::Error),
    #[error("{0}")]
    WriteScene(std::io::Error),
    #[error("{0}")]
    WriteStl(StlError),
    /// The mesh scene, read back, is refused.
    #[error("{0}")]
    Scene(SceneError),
    /// The analytic or the mesh run stopped short: each one's failure (`None`: it converged).
    #[error("{name}: a run did not converge ({analytic:?}, {mesh:?})")]
    NotConverged {
        name: &'static str,
        analytic: Option<DrawingFailure>,
        mesh: Option<DrawingFailure>,
    },
}

impl serde::Serialize for MeshBenchError {
    /// As its message (`bench --json`'s `failure`).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// The spacing that gives a tool about [`TRIANGLES_PER_TOOL`], from its count at 2 mm.
fn spacing_for(count_at_2mm: usize) -> f64 {
    2.0 * (count_at_2mm as f64 / TRIANGLES_PER_TOOL).sqrt()
}

/// The mesh scene of `p`'s preset text `text`: its tools replaced by `punch.stl` and `die.stl`
/// in `dir`, the whole blank solved.
fn mesh_scene(text: &str, dir: &std::path::Path) -> Result<std::path::PathBuf, MeshBenchError> {
    let mut table: toml::Table = text.parse().map_err(MeshBenchError::PresetToml)?;
    let mut tools = toml::Table::new();
    tools.insert("kind".into(), "mesh".into());
    tools.insert("punch".into(), "punch.stl".into());
    tools.insert("die".into(), "die.stl".into());
    table.insert("tools".into(), toml::Value::Table(tools));
    if let Some(toml::Value::Table(mesh)) = table.get_mut("mesh") {
        mesh.insert("symmetry".into(), "full".into());
    }
    let path = dir.join("scene.toml");
    std::fs::write(
        &path,
        toml::to_string(&table).map_err(MeshBenchError::SceneToml)?,
    )
    .map_err(MeshBenchError::WriteScene)?;
    Ok(path)
}

/// The mesh run `b` against the analytic run `a`: max shear (°), punch force (relative) and
/// draw-in (mm).
pub fn departures(a: &DrawingResult, b: &DrawingResult) -> [f64; 3] {
    [
        b.max_shear().1 - a.max_shear().1,
        b.punch_force_n / a.punch_force_n - 1.0,
        b.draw_in_mm - a.draw_in_mm,
    ]
}

fn compare(name: &'static str, text: &str, repetitions: usize) -> Result<MeshRun, MeshBenchError> {
    let mut p: DrawingProblem = preset(text, name, &[]);
    p.symmetry = Symmetry::Full;
    let coarse = tool_surfaces(&p.tooling, p.blank_mm, p.stroke_mm, 2.0);
    let spacing_mm = [
        spacing_for(coarse.0.triangles.len()),
        spacing_for(coarse.1.triangles.len()),
    ];
    let punch = tool_surfaces(&p.tooling, p.blank_mm, p.stroke_mm, spacing_mm[0]).0;
    let die = tool_surfaces(&p.tooling, p.blank_mm, p.stroke_mm, spacing_mm[1]).1;
    let dir = tempfile::tempdir().map_err(MeshBenchError::TempFolder)?;
    crate::stl::write_binary(&dir.path().join("punch.stl"), &punch)
        .map_err(MeshBenchError::WriteStl)?;
    crate::stl::write_binary(&dir.path().join("die.stl"), &die)
        .map_err(MeshBenchError::WriteStl)?;
    let scene_path = mesh_scene(text, dir.path())?;
    let (mut analytic_s, mut mesh_s, mut read_s) = (Vec::new(), Vec::new(), Vec::new());
    let mut last = None;
    for _ in 0..repetitions.max(1) {
        let t = Instant::now();
        let a = crate::core::drawing::solve(&p, &mut |_| {});
        analytic_s.push(t.elapsed().as_secs_f64());
        crate::scene::forget_mesh_tools();
        let t = Instant::now();
        let scene =
            crate::scene::Scene::load(Some(&scene_path), &[]).map_err(MeshBenchError::Scene)?;
        read_s.push(t.elapsed().as_secs_f64());
        let mut q = scene.to_problem();
        q.solver.parallel = false;
        let b = crate::core::drawing::solve(&q, &mut |_| {});
        mesh_s.push(t.elapsed().as_secs_f64());
        if !(a.converged && b.converged) {
            return Err(MeshBenchError::NotConverged {
                name,
                analytic: a.failure,
                mesh: b.failure,
            });
        }
        last = Some((a, b));
    }
    let (a, b) = last.expect("one repetition at least");
    Ok(MeshRun {
        name,
        triangles: [punch.triangles.len(), die.triangles.len()],
        spacing_mm,
        analytic_s: median(analytic_s),
        mesh_s: median(mesh_s),
        read_s: median(read_s),
        departures: departures(&a, &b),
        steps: [a.stats.steps, b.stats.steps],
        newton_iterations: [a.stats.newton_iterations, b.stats.newton_iterations],
    })
}

/// The open and the tight box and the hemisphere, each with ~100 000-triangle tools.
pub fn mesh_tools(repetitions: usize) -> Vec<Result<MeshRun, MeshBenchError>> {
    let hemisphere = include_str!("../../presets/hemisphere.toml");
    vec![
        compare("open box", PAPER_BOX_OPEN, repetitions),
        compare("tight box", PAPER_BOX_TIGHT, repetitions),
        compare("hemisphere", hemisphere, repetitions),
    ]
}
