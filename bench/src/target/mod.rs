//! The measuring harness the bench images share on the target (QEMU, semihosting): each image
//! in `src/bin/` is its `main` calling one of these `run`s.

pub mod estimate;
pub mod law;
#[cfg(feature = "mavlink")]
pub mod mavlink;
pub mod probe;
#[cfg(feature = "mavlink")]
pub mod replay;
#[cfg(feature = "serial")]
pub mod serial;
#[cfg(feature = "tables")]
pub mod table;
pub mod team;
