//! The test specimens the laws are checked and identified on: the bias-extension test
//! ([`bias`]) and its wrinkling ([`bias_wrinkle`]), the heavy cantilever ([`cantilever`]), the
//! Euler strip ([`euler_strip`]), and the strip driver they share ([`strip`]).

pub mod bias;
pub mod bias_wrinkle;
pub mod cantilever;
pub mod euler_strip;
pub mod strip;
