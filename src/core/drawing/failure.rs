//! Why a drawing has no result, or only part of one.

use crate::core::solver::{BadElement, Failure};

/// What holds the blank in its plane is missing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unrestrained {
    /// No friction between the fabric and the tools.
    NoFriction,
    /// No blank-holder pressure.
    NoHolder,
}

/// Why a drawing stopped short or never started.
#[derive(Clone, Debug, PartialEq)]
pub enum DrawingFailure {
    /// The model has no unique answer: the fabric has no shear stiffness in its plane (and,
    /// without `bends`, no bending stiffness either), so with nothing to pull against its
    /// yarns stay slack and any drape of the blank is an equilibrium.
    NoUniqueShape { why: Unrestrained, bends: bool },
    /// An element of the initial mesh is unusable.
    BadElement(BadElement),
    /// The solver stopped short of the full stroke.
    Solver(Failure),
    /// Bending was asked for on a blank that is not meshed as a grid of lines: the hinges have
    /// no line to run along (every drawing's blank is a grid; a guard, not a user's case).
    BendingOffYarnLines,
}

impl std::fmt::Display for DrawingFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DrawingFailure::NoUniqueShape { why, bends } => {
                let cause = match why {
                    Unrestrained::NoFriction => {
                        "there is no friction (process.friction = 0), so nothing holds the \
                         flange back"
                    }
                    Unrestrained::NoHolder => {
                        "there is no holder pressure (process.holder_pressure = 0), so the \
                         flange is pressed by nothing and friction has nothing to act on"
                    }
                };
                let fabric = if *bends {
                    "The fabric's bending stiffness resists only its curvature: in its plane it \
                     has no shear stiffness"
                } else {
                    "The paper's fabric has no shear and no bending stiffness"
                };
                write!(
                    f,
                    "no unique shape: {cause}. {fabric}, so the yarns stay slack and any drape \
                     of the blank is an equilibrium: shear and tension are not determined. Set \
                     process.friction > 0 and process.holder_pressure > 0 (or \
                     process.holder_force)"
                )
            }
            DrawingFailure::BadElement(e) => write!(f, "{e}"),
            DrawingFailure::Solver(e) => write!(f, "{e}"),
            DrawingFailure::BendingOffYarnLines => write!(
                f,
                "bending needs a blank meshed as a grid of lines: the hinges run along them"
            ),
        }
    }
}

impl std::error::Error for DrawingFailure {}
