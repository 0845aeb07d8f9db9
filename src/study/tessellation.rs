//! A scene's punch and die as closed triangle surfaces (what `wovenform tools` writes as STL):
//! tessellated from the analytic tools on a grid, or, for tools read from STL, as read. The
//! spacing's bounds are checked first, so a grid that would not fit costs nothing.

use crate::core::drawing::Tooling;
use crate::core::tools::capped::{grid_points, tool_surfaces};
use crate::core::tools::surface::TriSurface;
use crate::machine::memory_budget_bytes;
use crate::scene::{Scene, ToolKind};

/// Memory per grid point while tessellating, bytes (its field value, its cell's vertex index,
/// and the surface built on it).
const BYTES_PER_GRID_POINT: f64 = 16.0;

/// The punch and the die, and where they came from.
pub struct ToolSurfaces {
    /// `("punch", surface)` and `("die", surface)`.
    pub tools: [(&'static str, TriSurface); 2],
    /// The STL files they were read from (tools from STL), else `None`.
    pub read_from: Option<[String; 2]>,
    /// Time to tessellate, s (0 for tools read from STL).
    pub wall_s: f64,
}

/// Why a tessellation's spacing is refused, with the spacing asked for (mm) and the bound it
/// crosses.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpacingError {
    #[error("--spacing {spacing_mm}: expected a positive length in mm")]
    NotPositive { spacing_mm: f64 },
    #[error(
        "--spacing {spacing_mm} mm is coarser than the tools' smallest radius \
         ({smallest_radius_mm} mm): expected at most {smallest_radius_mm} mm"
    )]
    CoarserThanTools {
        spacing_mm: f64,
        smallest_radius_mm: f64,
    },
    #[error(
        "--spacing {spacing_mm} mm needs {points:.3e} grid points ({:.1} GB), over this \
         machine's {:.1} GB: expected --spacing ≥ {fits_from_mm:.3} mm",
        bytes / 1e9,
        budget_bytes / 1e9
    )]
    GridTooLarge {
        spacing_mm: f64,
        points: f64,
        /// The grid's memory and what this machine allows, bytes.
        bytes: f64,
        budget_bytes: f64,
        /// The finest spacing whose grid fits.
        fits_from_mm: f64,
    },
}

/// Refuses a spacing that is not a positive length, that is coarser than the tools' smallest
/// radius (the shape would be lost), or whose grid does not fit in memory. Tools from STL are
/// written as read: no spacing applies.
pub fn check_spacing(scene: &Scene, spacing: f64) -> Result<(), SpacingError> {
    if scene.tools.kind == ToolKind::Mesh {
        return Ok(());
    }
    if !(spacing.is_finite() && spacing > 0.0) {
        return Err(SpacingError::NotPositive {
            spacing_mm: spacing,
        });
    }
    let smallest_radius = scene.tools.smallest_radius_mm();
    if spacing > smallest_radius {
        return Err(SpacingError::CoarserThanTools {
            spacing_mm: spacing,
            smallest_radius_mm: smallest_radius,
        });
    }
    let problem = scene.to_problem();
    let points = grid_points(
        &problem.tooling,
        problem.blank_mm,
        problem.stroke_mm,
        spacing,
    );
    let (bytes, budget) = (BYTES_PER_GRID_POINT * points, memory_budget_bytes());
    if bytes > budget {
        // The grid's points fall as 1/spacing³.
        return Err(SpacingError::GridTooLarge {
            spacing_mm: spacing,
            points,
            bytes,
            budget_bytes: budget,
            fits_from_mm: spacing * (bytes / budget).cbrt() * 1.01,
        });
    }
    Ok(())
}

/// The scene's tools as closed surfaces on a grid of `spacing` mm (checked with
/// [`check_spacing`] first), or as read from their STL.
pub fn tessellate(scene: &Scene, spacing: f64) -> ToolSurfaces {
    let problem = scene.to_problem();
    if let Tooling::Mesh { punch, die } = &problem.tooling {
        return ToolSurfaces {
            tools: [("punch", punch.surface()), ("die", die.surface())],
            read_from: Some([punch.name.clone(), die.name.clone()]),
            wall_s: 0.0,
        };
    }
    let start = std::time::Instant::now();
    let (punch, die) = tool_surfaces(
        &problem.tooling,
        problem.blank_mm,
        problem.stroke_mm,
        spacing,
    );
    ToolSurfaces {
        tools: [("punch", punch), ("die", die)],
        read_from: None,
        wall_s: start.elapsed().as_secs_f64(),
    }
}
