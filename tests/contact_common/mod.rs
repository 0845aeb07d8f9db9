//! Shared by the contact benchmarks (`capstan.rs`, `holder_pull_out.rs`): the paper's fabric
//! with the linear yarn law, and contact terms sized from a model as the drawing sizes them.
#![allow(dead_code)]

use wovenform::core::contact::{Contact, ContactOptions, Holder, ToolMotion};
use wovenform::core::drawing::node_shares;
use wovenform::core::fabric::law::{CellLaw, CellParams};
use wovenform::core::solver::Model;

/// The paper's glass fabric with the linear yarn law (undulation off).
pub fn linear_fabric() -> CellLaw {
    let mut p = CellParams::PAPER_GLASS;
    p.undulation = false;
    CellLaw::new(p)
}

/// Contact of `model`'s nodes with `tools` (and the `holder`), friction `friction`, for
/// elements of about `h` mm: slip regularisation and contact smoothing 0.01 h, the penalty
/// factor 10 of the drawing.
pub fn contact_for(
    model: &Model,
    tools: Vec<ToolMotion>,
    holder: Option<Holder>,
    friction: f64,
    h: f64,
) -> Contact {
    let (area, cells) = node_shares(model);
    Contact::new(
        tools,
        holder,
        ContactOptions {
            friction,
            slip_regularisation: 0.01 * h,
            penalty_factor: 10.0,
            contact_smoothing: 0.01 * h,
            lagged: false,
        },
        area,
        &cells,
        model.law.stiffness_per_cell(),
        2.0 * h,
    )
}
