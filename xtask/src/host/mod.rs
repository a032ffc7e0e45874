//! The law on the host: the CSV doors (`eval`, `sim`), the adversary report and the plots.

pub mod csv;
pub mod eval;
pub mod field;
pub mod options;
pub mod plot;
pub mod report;
pub mod sim;
