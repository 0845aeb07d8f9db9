//! The fabric's laws, in the paper's order: the biaxial woven-cell law with its crimp
//! interchange ([`law`]), the toe that starts a slack yarn's stiffness smoothly ([`toe`]), the
//! in-plane shear law ([`shear`]) and, beyond the paper, the yarns' bending ([`bending`]).

pub mod bending;
pub mod law;
pub mod shear;
pub mod toe;
