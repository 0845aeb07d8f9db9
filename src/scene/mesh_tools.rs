//! Reading a mesh scene's tools: `tools.punch` and `tools.die` are STL files, relative to the
//! scene file. Each is read, checked as a closed outward-facing surface, placed (the punch's
//! lowest point and the die's face in z = 0), and the pair is checked over the stroke (the
//! punch neither starts in the die nor runs into it), the blank's edge on the die's face.
//!
//! A tool read once is kept for the process (keyed by its file's path, size and time and the
//! lattice), so every design of a sweep shares it and the distance samples it has computed.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use crate::core::tools::mesh_tool::{MeshTool, Role};

use super::types::{LoadedTools, ToolKind};
use super::{Scene, SceneError};

/// Within this distance of the surface a tool's distance is interpolated, mm.
const BAND_MM: f64 = 1.0;

type Key = (PathBuf, u64, Option<std::time::SystemTime>, u64, bool);

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

/// Reads (or finds already read) the tool at `path` as a `role`.
fn tool(path: &Path, role: Role, lattice: f64) -> Result<Arc<MeshTool>, String> {
    let meta =
        std::fs::metadata(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    let key = (
        canonical,
        meta.len(),
        meta.modified().ok(),
        lattice.to_bits(),
        role == Role::Punch,
    );
    if let Some(t) = cache().lock().unwrap().get(&key) {
        return Ok(t.clone());
    }
    let surface = crate::stl::read_surface(path).map_err(|e| e.to_string())?;
    let name = key.0.display().to_string();
    let tool = MeshTool::new(role, &name, &surface, lattice, BAND_MM)
        .map_err(|e| format!("{name}: {e}"))?;
    let tool = Arc::new(tool);
    cache().lock().unwrap().insert(key, tool.clone());
    Ok(tool)
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
        let read = |file: &str, role| tool(&resolve(origin, file), role, t.lattice);
        // The two files are read side by side.
        let (punch, die) = rayon::join(|| read(&t.punch, Role::Punch), || read(&t.die, Role::Die));
        let named = |key: &str, file: &str, e: String| {
            fail(key, &[key], format!("{key} = \"{file}\": {e}"))
        };
        let punch = punch.map_err(|e| named("tools.punch", &t.punch, e))?;
        let die = die.map_err(|e| named("tools.die", &t.die, e))?;
        let stroke = self.process.stroke;
        let pair_key = (
            Arc::as_ptr(&punch) as usize,
            Arc::as_ptr(&die) as usize,
            stroke.to_bits(),
        );
        let checked = pair_cache().lock().unwrap().get(&pair_key).cloned();
        let checked = checked.unwrap_or_else(|| {
            let r = MeshTool::check_pair(&punch, &die, stroke).map_err(|e| e.to_string());
            pair_cache().lock().unwrap().insert(pair_key, r.clone());
            r
        });
        checked.map_err(|e| {
            let keys = ["tools.punch", "tools.die", "process.stroke"];
            fail(
                "tools.punch",
                &keys,
                format!(
                    "tools.punch = \"{}\" and tools.die = \"{}\": {e}",
                    t.punch, t.die
                ),
            )
        })?;
        self.check_blank_on_face(&die, origin_of)?;
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

    /// The blank's edge must rest on the die's face (where the holder presses it).
    fn check_blank_on_face(
        &self,
        die: &MeshTool,
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
            return Err(SceneError {
                origin: origin_of(&keys),
                key: Some("blank.size".into()),
                detail: format!(
                    "blank.size = {}: the blank's edge at ({:.1}, {:.1}) mm is not on the die's \
                     face in z = 0 ({}); expected a blank whose whole edge rests on the face, \
                     where the holder presses it",
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
