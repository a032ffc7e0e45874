//! The firmware on the host's side: building the images, running them in their emulators (QEMU,
//! rp2040js), the closed loop with the host simulator (`cargo xtask run`), and the emulated
//! checks of `cargo xtask test`.

pub mod build;
pub mod closed_loop;
pub mod emulator;
pub mod mavlink;
pub mod mavlink_field;
pub mod qemu;
pub mod rp2040js;
pub mod run;
pub mod signing;
pub mod size;
pub mod tables;
