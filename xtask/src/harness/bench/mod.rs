//! The bench images on the target (`bench/`): each one built, run in QEMU with `-icount`, and
//! what it prints read back: the law ([`law`]), the serial loop ([`serial`]), the MAVLink
//! endpoint ([`mavlink`]), the estimator ([`estimate`]), a value-table lookup ([`table`]), a team's period ([`team`]).

pub mod estimate;
pub mod image;
pub mod law;
pub mod mavlink;
pub mod serial;
pub mod table;
pub mod team;
