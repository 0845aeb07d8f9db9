//! The solver and the biaxial law: pure numerics, no files, no terminal, no serde.
//!
//! Data flows one way: a [`membrane::mesh::Mesh`] and a [`fabric::law::CellLaw`] make a [`solver::Model`]; a
//! [`solver::Solver`] drives it along the load path with prescribed displacements and nodal terms
//! (contact, pressure); the model then gives shear angles, tensions and forces.
// Index loops mirror the paper's index notation (α, β, k, m); keep them.
#![allow(clippy::needless_range_loop)]

// The folders in the paper's order: fabric, membrane, sparse, solver, tools, contact, wrinkles,
// drawing, specimens; each uses only those before it (`guide::layers` checks it).
pub mod contact;
pub mod drawing;
pub mod fabric;
pub mod membrane;
pub mod solver;
pub mod sparse;
pub mod specimens;
pub mod tools;
pub mod vec3;
pub mod wrinkles;
