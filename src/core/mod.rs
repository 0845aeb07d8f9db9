//! The solver and the biaxial law: pure numerics, no files, no terminal, no serde.
//!
//! Data flows one way: a [`mesh::Mesh`] and a [`law::CellLaw`] make a [`solver::Model`]; a
//! [`solver::Solver`] drives it along the load path with prescribed displacements and nodal terms
//! (contact, pressure); the model then gives shear angles, tensions and forces.
// Index loops mirror the paper's index notation (α, β, k, m); keep them.
#![allow(clippy::needless_range_loop)]

pub mod bending;
pub mod bias;
pub mod bias_wrinkle;
pub mod cantilever;
pub mod conjugate;
pub mod contact;
pub mod drawing;
pub mod element;
pub mod euler_strip;
pub mod law;
pub mod linear;
pub mod mesh;
pub mod pattern;
pub mod shear;
pub mod solver;
pub mod split_cholesky;
pub mod strip;
pub mod toe;
pub mod tools;
pub mod trigger;
pub mod vec3;
pub mod wrinkle;
