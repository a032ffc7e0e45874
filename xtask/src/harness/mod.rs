//! Where the code runs, driven from the host: the law on the host simulator ([`host`]), the
//! images in their emulators with the serial and MAVLink closed loops ([`firmware`]), the
//! bench images on the target ([`mod@bench`]), the libFuzzer targets ([`fuzz`]), and the autopilots'
//! SITL: what both chases share ([`autopilot`]), then [`ardupilot`] and [`px4`].

pub mod ardupilot;
pub mod autopilot;
pub mod bench;
pub mod firmware;
pub mod fuzz;
pub mod host;
pub mod px4;
