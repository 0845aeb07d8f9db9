//! Sparse algebra for the tangent: its pattern ([`pattern`]), the tangent and its solve
//! ([`linear`]), the Cholesky factorization and its two-thread split ([`split_cholesky`]), and
//! conjugate gradients for the small symmetric systems beside it ([`conjugate`]).

pub mod conjugate;
pub mod linear;
pub mod pattern;
pub mod split_cholesky;
