//! The firmware on the host's side: building the images, running them in QEMU, the closed loop
//! with the host simulator (`cargo xtask run`), and the QEMU checks of `cargo xtask test`.

pub mod build;
pub mod closed_loop;
pub mod mavlink;
pub mod qemu;
pub mod run;
pub mod size;
pub mod tables;
pub mod tests;
