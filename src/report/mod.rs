//! Reports: charts (PNG), tables (CSV) and the paper's figures reproduced from the law.
pub mod figure6;
pub mod plot;
