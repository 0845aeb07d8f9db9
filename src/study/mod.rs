//! The studies that drive the core: a sweep of designs, a convergence study, the law's fit to
//! measured curves and the benchmark. Each takes plain data (a plan, a scene, a table of
//! measurements) and gives plain data back; what they draw or print is in [`crate::report`].
pub mod bench;
pub mod converge;
pub mod draw;
pub mod estimate;
pub mod fit;
pub mod frontier;
pub mod mesh_bench;
pub mod scaling;
pub mod slurm;
pub mod sweep;
pub mod tessellation;
pub mod timing;
