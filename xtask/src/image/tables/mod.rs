//! The game's value tables as xtask makes them: which limits on which grids ([`sets`]), solved
//! with the `hji` crate and kept in `target/hj-cache/` and the machine's cache ([`solve`]).
//! `cargo xtask hj`, the images that carry tables and the plots read them here.

pub mod sets;
pub mod solve;
