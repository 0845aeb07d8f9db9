//! Reading a mesh scene's tools: `tools.punch` and `tools.die` are STL files, relative to the
//! scene file. Each is read, checked as a closed outward-facing surface, placed (the punch's
//! lowest point and the die's face in z = 0), and the pair is checked over the stroke (the
//! punch neither starts in the die nor runs into it), the blank's edge on the die's face.
//!
//! Before anything is built from a tool, its size is checked against the blank, the elements
//! and the stroke (a tool in metres or inches is named as one: `core::tools::scale`), and its
//! tables are sized where the fabric can reach (the blank, a margin and the stroke) and
//! checked against the memory a run may take.
//!
//! A file read once is kept for the process (keyed by its path, size and modification time:
//! a file written anew is read anew), and so is each tool built from it (keyed by the file,
//! the lattice and where the fabric can reach), so every design of a sweep shares it and the
//! distance samples it has computed.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use crate::core::tools::mesh_tool::{Limits, MeshTool, PlacementError, Role, footprint};
use crate::core::tools::sampled::Box3;
use crate::core::tools::scale::{self, Setting};
use crate::core::tools::surface::TriSurface;
use crate::machine::memory_budget_bytes;
use crate::show::show_bytes;

use super::types::{LoadedTools, ToolKind};
use super::{Scene, SceneError};

/// Within this distance of the surface a tool's distance is interpolated, mm.
const BAND_MM: f64 = 1.0;

/// A file as read: its path, size and modification time.
type FileKey = (PathBuf, u64, Option<std::time::SystemTime>);
/// A tool: its file, lattice, role and reach (as bits).
type Key = (FileKey, u64, bool, [u64; 6]);

fn surfaces() -> &'static Mutex<HashMap<FileKey, Arc<TriSurface>>> {
    static CACHE: std::sync::OnceLock<Mutex<HashMap<FileKey, Arc<TriSurface>>>> =
        std::sync::OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

fn cache() -> &'static Mutex<HashMap<Key, Arc<MeshTool>>> {
    static CACHE: std::sync::OnceLock<Mutex<HashMap<Key, Arc<MeshTool>>>> =
        std::sync::OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Punch, die and stroke of a checked pair, and the outcome.
type Pairs = Mutex<HashMap<(usize, usize, u64), Result<(), String>>>;

fn pair_cache() -> &'static Pairs {
    static CACHE: std::sync::OnceLock<Pairs> = std::sync::OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Forgets the tools read so far (the next scene reads its files again): for timing reads.
pub fn forget_mesh_tools() {
    surfaces().lock().unwrap().clear();
    cache().lock().unwrap().clear();
    pair_cache().lock().unwrap().clear();
}

/// Where a tool path written in a scene from `origin` points.
pub fn resolve(origin: &str, path: &str) -> PathBuf {
    let p = Path::new(path);
    if p.is_absolute() {
        return p.to_path_buf();
    }
    match Path::new(origin).parent() {
        Some(dir) if Path::new(origin).is_file() => dir.join(p),
        _ => p.to_path_buf(),
    }
}

/// The surface in the file at `path`, read (and checked) once per version of the file.
fn surface(path: &Path) -> Result<(FileKey, Arc<TriSurface>), String> {
    let meta =
        std::fs::metadata(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    let key = (canonical, meta.len(), meta.modified().ok());
    if let Some(s) = surfaces().lock().unwrap().get(&key) {
        return Ok((key, s.clone()));
    }
    let surface = Arc::new(crate::stl::read_surface(path).map_err(|e| e.to_string())?);
    surfaces()
        .lock()
        .unwrap()
        .insert(key.clone(), surface.clone());
    Ok((key, surface))
}

/// Where the fabric can be in a tool's own frame: the blank's plan (the blank only draws in)
/// grown by a tenth of its larger side, two elements (the holder's grip fades in over one)
/// and 5 mm, and the stroke (the punch's frame moves with it) and that margin in z. Outside,
/// the distance is still exact, only not sampled.
fn reach(role: Role, s: &Setting) -> Box3 {
    let margin = 0.1 * s.blank[0].max(s.blank[1]) + 2.0 * s.element_mm + 5.0;
    let [hx, hy] = s.blank.map(|b| 0.5 * b + margin);
    let z = s.stroke_mm + margin;
    let top = if role == Role::Punch { z } else { margin };
    ([-hx, -hy, -z], [hx, hy, top])
}

/// Reads (or finds already read) the tool at `path` as a `role` for the drawing `setting`:
/// refused when its size cannot draw that blank, or its tables would not fit in memory.
fn tool(path: &Path, role: Role, lattice: f64, setting: &Setting) -> Result<Arc<MeshTool>, String> {
    let (file, surface) = surface(path)?;
    let name = file.0.display().to_string();
    scale::check(role, surface.bounds(), setting).map_err(|e| format!("{name}: {e}"))?;
    let reach = reach(role, setting);
    let bits = [0, 1, 2, 3, 4, 5].map(|i| [reach.0, reach.1][i / 3][i % 3].to_bits());
    let key = (file, lattice.to_bits(), role == Role::Punch, bits);
    if let Some(t) = cache().lock().unwrap().get(&key) {
        return Ok(t.clone());
    }
    let limits = Limits {
        reach,
        budget_bytes: memory_budget_bytes(),
    };
    let tool = MeshTool::within(role, &name, &surface, lattice, BAND_MM, &limits).map_err(|e| {
        format!(
            "{name}: {}",
            placement_words(e, role, &surface, lattice, setting)
        )
    })?;
    let tool = Arc::new(tool);
    cache().lock().unwrap().insert(key, tool.clone());
    Ok(tool)
}

/// A placement error in words, with what only this layer knows: the memory in units, the
/// lattice that would fit, the unit a die far too large was likely written in.
fn placement_words(
    e: PlacementError,
    role: Role,
    surface: &TriSurface,
    lattice: f64,
    setting: &Setting,
) -> String {
    match e {
        PlacementError::TooLarge {
            total,
            part,
            part_bytes,
            limit,
        } => {
            let reach = reach(role, setting);
            let need = |h: f64| -> f64 {
                footprint(role, surface, h, BAND_MM, reach)
                    .iter()
                    .map(|p| p.1)
                    .sum()
            };
            let coarser = (1..40)
                .map(|k| lattice * 1.25f64.powi(k))
                .find(|&h| h <= 5.0 && need(h) <= limit);
            let advice = match coarser {
                Some(h) => format!("expected tools.lattice ≥ {h:.2} mm, or a smaller blank"),
                None => "expected a coarser mesh of the tool, or a smaller blank".into(),
            };
            format!(
                "its tables (with tools.lattice = {lattice} mm) would need about {} (its {part}: \
                 {}), but a run may use at most {} on this machine (80 % of what is \
                 available): {advice}",
                show_bytes(total),
                show_bytes(part_bytes),
                show_bytes(limit)
            )
        }
        PlacementError::FaceNotUnderBlank { .. } => {
            let b = surface.bounds();
            let hint = scale::hint(role, b, setting, true);
            format!(
                "{e}; the die is {:.0} × {:.0} mm in plan. {hint}",
                b.1[0] - b.0[0],
                b.1[1] - b.0[1]
            )
        }
        e => e.to_string(),
    }
}

impl Scene {
    /// Reads the scene's mesh tools (a scene of another kind is left as it is). `origin` is
    /// the scene file; `origin_of` names who set the keys of a failure.
    pub(super) fn read_mesh_tools(
        &mut self,
        origin: &str,
        origin_of: &dyn Fn(&[&str]) -> String,
    ) -> Result<(), SceneError> {
        if self.tools.kind != ToolKind::Mesh {
            return Ok(());
        }
        let fail = |key: &str, keys: &[&str], detail: String| SceneError {
            origin: origin_of(keys),
            key: Some(key.to_string()),
            detail,
        };
        let t = &self.tools;
        let setting = Setting {
            blank: self.blank.size.0,
            element_mm: self.mesh.element_size,
            stroke_mm: self.process.stroke,
        };
        // A path no file system takes (PATH_MAX is 4096 bytes) is refused before it is quoted
        // back or looked up.
        for (key, file) in [("tools.punch", &t.punch), ("tools.die", &t.die)] {
            if file.len() > 4096 {
                let detail = format!(
                    "{key} = \"{}\": a path of {} bytes; expected the path of an STL file \
                     (at most 4096 bytes)",
                    super::overrides::excerpt(file),
                    file.len()
                );
                return Err(fail(key, &[key], detail));
            }
        }
        let read = |file: &str, role| tool(&resolve(origin, file), role, t.lattice, &setting);
        // The two files are read side by side.
        let (punch, die) = rayon::join(|| read(&t.punch, Role::Punch), || read(&t.die, Role::Die));
        let named = |key: &str, file: &str, e: String| {
            fail(key, &[key], format!("{key} = \"{file}\": {e}"))
        };
        let punch = punch.map_err(|e| named("tools.punch", &t.punch, e))?;
        let die = die.map_err(|e| named("tools.die", &t.die, e))?;
        let stroke = self.process.stroke;
        self.check_pair(&punch, &die, origin_of)?;
        self.check_blank_on_face(&die, &setting, origin_of)?;
        let [bx, by] = self.blank.size.0;
        let lo = [-0.5 * bx, -0.5 * by, -stroke - 1.0];
        let hi = [0.5 * bx, 0.5 * by, stroke + 1.0];
        let smallest_radius_mm = punch
            .smallest_radius_mm(lo, hi)
            .min(die.smallest_radius_mm(lo, hi));
        // The files as absolute paths: a written scene (summary.json's inputs) runs back from
        // anywhere.
        self.tools.punch = punch.name.clone();
        self.tools.die = die.name.clone();
        self.tools.loaded = Some(LoadedTools {
            punch,
            die,
            smallest_radius_mm,
        });
        Ok(())
    }

    /// The punch must enter the die's opening over the whole stroke: checked once per pair of
    /// tools and stroke (the explorer asks at every key).
    fn check_pair(
        &self,
        punch: &Arc<MeshTool>,
        die: &Arc<MeshTool>,
        origin_of: &dyn Fn(&[&str]) -> String,
    ) -> Result<(), SceneError> {
        let t = &self.tools;
        let stroke = self.process.stroke;
        let pair_key = (
            Arc::as_ptr(punch) as usize,
            Arc::as_ptr(die) as usize,
            stroke.to_bits(),
        );
        let checked = pair_cache().lock().unwrap().get(&pair_key).cloned();
        let checked = checked.unwrap_or_else(|| {
            let r = MeshTool::check_pair(punch, die, stroke).map_err(|e| e.to_string());
            pair_cache().lock().unwrap().insert(pair_key, r.clone());
            r
        });
        checked.map_err(|e| {
            let keys = ["tools.punch", "tools.die", "process.stroke"];
            // The sizes that say whether the punch fits the opening at all.
            let (lo, hi) = punch.bounds;
            let opening = die.flange.as_ref().map_or(String::new(), |f| {
                let [ox, oy] = f.opening_half();
                format!("; the die's opening reaches ±{ox:.1} mm along x and ±{oy:.1} mm along y")
            });
            SceneError {
                origin: origin_of(&keys),
                key: Some("tools.punch".to_string()),
                detail: format!(
                    "tools.punch = \"{}\" and tools.die = \"{}\": {e} (the punch is {:.1} × \
                     {:.1} mm in plan{opening})",
                    t.punch,
                    t.die,
                    hi[0] - lo[0],
                    hi[1] - lo[1]
                ),
            }
        })
    }

    /// The blank's edge must rest on the die's face (where the holder presses it).
    fn check_blank_on_face(
        &self,
        die: &MeshTool,
        setting: &Setting,
        origin_of: &dyn Fn(&[&str]) -> String,
    ) -> Result<(), SceneError> {
        let Some(flange) = die.flange.as_ref() else {
            return Ok(());
        };
        let [hx, hy] = self.blank.size.0.map(|v| 0.5 * v);
        let n = 16;
        let mut edge = Vec::new();
        for i in 0..=n {
            let s = -1.0 + 2.0 * i as f64 / n as f64;
            edge.extend([[s * hx, -hy], [s * hx, hy], [-hx, s * hy], [hx, s * hy]]);
        }
        if let Some(p) = edge.iter().find(|p| flange.distance(p[0], p[1]).0 < 0.0) {
            let keys = ["blank.size", "tools.die"];
            let [ox, oy] = flange.opening_half();
            // A die far larger than the blank: say which unit would bring it back.
            let hint = scale::hint(Role::Die, die.bounds, setting, true);
            let hint = if hint.is_empty() {
                String::new()
            } else {
                format!(" (or is the die too large? {hint})")
            };
            return Err(SceneError {
                origin: origin_of(&keys),
                key: Some("blank.size".into()),
                detail: format!(
                    "blank.size = {}: the blank's edge at ({:.1}, {:.1}) mm is not on the die's \
                     face in z = 0 ({}), whose opening reaches ±{ox:.1} mm along x and \
                     ±{oy:.1} mm along y; expected a blank whose whole edge rests on the face, \
                     where the holder presses it{hint}",
                    super::PlanPair(self.blank.size.0),
                    p[0],
                    p[1],
                    die.name
                ),
            });
        }
        Ok(())
    }
}
