//! The autopilots' SITL flying the pursuer (part of `cargo xtask test`): each check flies where
//! its SITL binary is found and says SKIPPED, and why, where not.

mod ardupilot_plane;
mod ardupilot_rover;
mod ardupilot_team;
mod px4_plane;
mod px4_rover;
mod skipped;

/// ArduPlane, then ArduPilot Rover.
pub fn ardupilot(record: &mut impl FnMut(&str, Result<String, String>)) {
    ardupilot_plane::record(record);
    ardupilot_rover::record(record);
}

/// Three ArduPilot Rover pursuers in a team against a fourth rover.
pub fn ardupilot_team(record: &mut impl FnMut(&str, Result<String, String>)) {
    ardupilot_team::record(record);
}

/// PX4's rover, then its airplane.
pub fn px4(record: &mut impl FnMut(&str, Result<String, String>)) {
    px4_rover::record(record);
    px4_plane::record(record);
}
