//! What every layer may use: the tools this machine needs ([`setup`]), where the workspace is
//! ([`workspace`]), progress of long work ([`progress`]).

pub mod progress;
pub mod setup;
pub mod workspace;
