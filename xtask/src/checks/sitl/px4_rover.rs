//! PX4 SITL's SIH Ackermann rover flying the pursuer, driven by the QEMU image and by the
//! companion binary.

use crate::harness::px4::{find, fly, Flown, Options};

/// The share of setpoints (one in this many) the course may flip side on: chatter on raw fixes
/// flips the turn up to 522 times a chase (docs/field.md); this rover's first chase flips on 2
/// to 7 of its 110 to 130 setpoints, the course jittering about the heading as it settles.
const FLIP_SHARE: usize = 10;

/// `cargo xtask test`'s PX4 chases: one start below the threshold against the straight evader,
/// the rover driven by the QEMU image's velocity setpoints, then by the companion binary's,
/// where PX4 SITL is found (said plainly where not).
pub fn record(record: &mut impl FnMut(&str, Result<String, String>)) {
    println!("== xtask test: PX4 SITL (SIH Ackermann rover) flying the pursuer, the MAVLink image its companion");
    if find(None).is_none() {
        println!("   SKIPPED: PX4 SITL not found (../shared/px4/bin/px4); docs/px4.md says what to build");
        return;
    }
    let options = Options {
        short: true,
        ..Options::default()
    };
    let image = fly(&options);
    record(
        "px4::rover_captures_through_velocity_setpoints_without_offboard_loss",
        image.as_ref().map_err(Clone::clone).and_then(check_chase),
    );
    let companion = fly(&Options {
        companion: true,
        ..options
    });
    record(
        "px4::the_companion_captures_as_the_qemu_image_within_a_control_period",
        companion
            .as_ref()
            .map_err(Clone::clone)
            .and_then(|c| check_alike(image.as_ref().map_err(Clone::clone)?, c)),
    );
}

/// The companion's chase (`companion`) captured, and within one TC_PERIOD of the QEMU image's
/// (`image`) capture time, each from its own PX4 instance.
fn check_alike(image: &Flown, companion: &Flown) -> Result<String, String> {
    let chase = check_chase(companion)?;
    let time = |f: &Flown| f.outcomes.first().and_then(|o| o.captured);
    let (Some(a), Some(b)) = (time(image), time(companion)) else {
        return Err("a chase was not captured".to_string());
    };
    let period = (companion.measured.response * 100.0).round() / 100.0;
    let line = format!(
        "the companion captured at {b:.2} s, the QEMU image at {a:.2} s: {:.2} s apart (TC_PERIOD {period:.2} s); {chase}",
        (a - b).abs()
    );
    if (a - b).abs() > period {
        return Err(line);
    }
    Ok(line)
}

/// Captured no later than the ideal Dubins pursuer + 3 s (the rover starts from rest), no
/// failsafe and no mode change during the chase, the setpoints' course flipping side on at most
/// one setpoint in [`FLIP_SHARE`].
fn check_chase(flown: &Flown) -> Result<String, String> {
    let o = flown.outcomes.first().ok_or("no chase flown")?;
    let captured = o.captured.ok_or("never captured")?;
    let failsafe = flown.failsafe_in_chase.first().copied().unwrap_or(true);
    let line = format!(
        "rover {:.2} m/s, {:.2} rad/s, heading response {:.2} s; law {:?}; captured at {captured:.2} s (ideal {:.2} s); {} sign flips in {} setpoints; {}; from the last setpoint, PX4's failsafe {} and standstill {}",
        flown.measured.speed,
        flown.measured.turn_rate,
        flown.measured.response,
        flown.limits,
        o.ideal,
        o.flips,
        o.setpoints,
        if failsafe { "PX4 LEFT OFFBOARD during the chase" } else { "OFFBOARD throughout" },
        crate::harness::autopilot::seconds(o.to_stop_message),
        crate::harness::autopilot::seconds(o.to_failsafe),
    );
    if captured > o.ideal + 3.0 || failsafe || o.flips * FLIP_SHARE > o.setpoints {
        return Err(line);
    }
    Ok(line)
}
