//! What a SITL check says where its autopilot's binary is missing.

/// Whether ArduPilot Rover SITL is missing; where it is, says SKIPPED and why.
pub fn rover_missing() -> bool {
    let missing = crate::harness::ardupilot::find_rover(None).is_none();
    if missing {
        println!(
            "   SKIPPED: ArduPilot Rover SITL not found (TWOCARS_ARDUROVER or \
             ../shared/ardupilot/ardurover); docs/ardupilot.md says how to build it"
        );
    }
    missing
}
