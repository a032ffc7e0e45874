//! The firmware's harnesses on the host: the images in their emulators (QEMU, rp2040js), the
//! closed loop with the host simulator (`cargo xtask run`), the pymavlink peer of the MAVLink
//! images, and the value tables an image carries. Building the images is [`crate::image`].

pub mod closed_loop;
mod defmt_log;
pub mod emulator;
pub mod mavlink;
pub mod mavlink_field;
pub mod qemu;
pub mod rp2040js;
pub mod run;
pub mod tables;
