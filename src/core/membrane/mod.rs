//! The blank as a membrane: its mesh of 4-node elements with the yarn directions ([`mesh`])
//! the element that turns nodal positions into yarn strains, shear and forces ([`element`]),
//! and the bending hinges along its yarn lines ([`hinges`]).

pub mod element;
pub mod hinges;
pub mod mesh;
