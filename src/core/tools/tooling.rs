//! The punch and die pair a drawing uses, by kind: a box, an ellipsoid, a hemisphere, or
//! triangle surfaces; each gives its two rigid tools and the die opening.

use std::sync::Arc;

use super::Tool;
use super::mesh_tool::MeshTool;

/// The punch and die pair.
#[derive(Clone, Debug, PartialEq)]
pub enum Tooling {
    /// A square (rectangular) box: punch sides `side` (mm), plan corner radius `r`, nose radius
    /// `rp`; die entry radius `rm`; die opening `side + 2·clearance`.
    Box {
        side: [f64; 2],
        r: f64,
        rp: f64,
        rm: f64,
        clearance: f64,
    },
    /// An ellipsoidal punch of semi-axes `[ax, ay, az]`; the die opening is its plan ellipse
    /// offset by the clearance.
    Ellipsoid {
        axes: [f64; 3],
        rm: f64,
        clearance: f64,
    },
    /// A hemispherical punch of radius `radius`.
    Hemisphere {
        radius: f64,
        rm: f64,
        clearance: f64,
    },
    /// A punch and a die from triangle surfaces (STL), placed by the user.
    Mesh {
        punch: Arc<MeshTool>,
        die: Arc<MeshTool>,
    },
}

impl Tooling {
    /// The punch (tip at z = 0) and the die.
    pub fn tools(&self) -> (Tool, Tool) {
        match *self {
            Tooling::Box {
                side,
                r,
                rp,
                rm,
                clearance,
            } => (
                Tool::box_punch(side, r, rp, 0.0),
                Tool::box_die(side, r, clearance, rm),
            ),
            Tooling::Ellipsoid {
                axes,
                rm,
                clearance,
            } => (
                Tool::EllipsoidPunch { axes, tip: 0.0 },
                Tool::elliptic_die([axes[0], axes[1]], clearance, rm),
            ),
            Tooling::Hemisphere {
                radius,
                rm,
                clearance,
            } => (
                Tool::EllipsoidPunch {
                    axes: [radius; 3],
                    tip: 0.0,
                },
                Tool::elliptic_die([radius, radius], clearance, rm),
            ),
            Tooling::Mesh { ref punch, ref die } => (
                Tool::Mesh {
                    shape: punch.clone(),
                    tip: 0.0,
                },
                Tool::Mesh {
                    shape: die.clone(),
                    tip: 0.0,
                },
            ),
        }
    }

    /// Half extents of the die opening in plan, mm.
    pub fn opening_half(&self) -> [f64; 2] {
        match *self {
            Tooling::Box {
                side, clearance, ..
            } => [0.5 * side[0] + clearance, 0.5 * side[1] + clearance],
            Tooling::Ellipsoid {
                axes, clearance, ..
            } => [axes[0] + clearance, axes[1] + clearance],
            Tooling::Hemisphere {
                radius, clearance, ..
            } => [radius + clearance; 2],
            Tooling::Mesh { ref die, .. } => {
                die.flange.as_ref().map_or([0.0; 2], |f| f.opening_half())
            }
        }
    }
}
