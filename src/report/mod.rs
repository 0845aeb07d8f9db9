//! Reports: charts (PNG), tables (CSV) and the paper's figures reproduced from the law; the
//! maps, VTU file and summary of a drawing run; the report sheet of a design sweep.
pub mod bench;
pub mod converge;
pub mod error;
pub mod figure6;
pub mod fit;
pub mod maps;
pub mod mirror;
pub mod plot;
pub mod sheet;
pub mod summary;
pub mod sweep;
pub mod vtu;
