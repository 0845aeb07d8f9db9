//! The test specimens the laws are checked and identified on: the bias-extension test
//! ([`bias`]) and its wrinkling (`bias_wrinkle`), the heavy cantilever ([`cantilever`]), the
//! Euler strip (`euler_strip`); what the strips share ([`strip`]), and the strip clamped at
//! both ends and shortened step by step that the Euler and the wrinkling strips are
//! (`clamped`). Those three are checks of the model that no command runs: they are compiled
//! for the tests only, their checks beside them.

pub mod bias;
pub mod cantilever;
pub mod strip;

#[cfg(test)]
mod bias_wrinkle;
#[cfg(test)]
mod clamped;
#[cfg(test)]
mod euler_strip;
