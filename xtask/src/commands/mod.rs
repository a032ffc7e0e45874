//! One module per command: its options and the work only it does. Nothing below this layer
//! imports it (`cargo xtask imports` checks); what two layers share lives below.

pub mod bench;
pub mod build;
pub mod csv;
pub mod eval;
pub mod field;
pub mod fuzz;
pub mod hj;
pub mod plot;
pub mod profile;
pub mod report;
pub mod run;
pub mod sim;
pub mod team;
