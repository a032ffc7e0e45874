//! ArduPilot Rover SITL flying the pursuer, the MAVLink image its companion: the chase, a
//! second rover as the evader, the unit's reading of ArduPilot's telemetry, and signing.

use crate::harness::ardupilot::{cost_line, fly, Flown, Options};
use crate::image::signing::SigningKey;

/// `cargo xtask test`'s chases: one start below the threshold against the straight evader,
/// simulated and then a second rover, with ArduPilot Rover SITL where it is found (said plainly
/// where not); the same start signed both ways.
pub fn record(record: &mut impl FnMut(&str, Result<String, String>)) {
    println!(
        "== xtask test: ArduPilot Rover SITL flying the pursuer, the MAVLink image its companion"
    );
    if super::skipped::rover_missing() {
        return;
    }
    let options = Options {
        ardurover: None,
        short: true,
        field: false,
        simulated: true,
        rover_evader: true,
        companion: false,
        key: None,
    };
    let flown = fly(&options);
    record(
        "ardupilot::rover_sitl_captures_and_stops_when_the_target_goes_stale",
        flown.as_ref().map_err(Clone::clone).and_then(check_chase),
    );
    record(
        "ardupilot::a_second_rover_as_the_evader_is_captured",
        flown
            .as_ref()
            .map_err(Clone::clone)
            .and_then(check_rover_evader),
    );
    record(
        "ardupilot::the_unit_parses_ardupilots_telemetry_with_nothing_dropped",
        flown
            .as_ref()
            .map_err(Clone::clone)
            .and_then(check_telemetry),
    );
    let signed = SigningKey::for_tests().and_then(|key| {
        fly(&Options {
            rover_evader: false,
            key: Some(key),
            ..options.clone()
        })
    });
    record(
        "ardupilot::signed_both_ways_the_rover_captures_and_nothing_is_refused",
        signed.as_ref().map_err(Clone::clone).and_then(check_signed),
    );
}

/// Captured no later than the ideal Dubins pursuer + 3 s (the rover starts from rest: about
/// 1.5 s of that); the unit's "target stale" within TC_TIMEOUT of capture; ArduPilot's stop 3 s
/// after the unit's last setpoint and a standstill within 8 s of it.
fn check_chase(flown: &Flown) -> Result<String, String> {
    let o = flown.outcomes.first().ok_or("no chase flown")?;
    let captured = o.captured.ok_or("never captured")?;
    let stop = o.to_stop_message.ok_or("ArduPilot never said it stopped")?;
    let still = o.to_failsafe.ok_or("the rover never stood still")?;
    let stale = o
        .unit_stale_after
        .ok_or("the unit never said the target was stale")?;
    if captured > o.ideal + 3.0 || !(2.9..=3.2).contains(&stop) || still > 8.0 || stale > 1.05 {
        return Err(format!(
            "captured {captured:.2} s (ideal {:.2} s), stop {stop:.2} s, standstill {still:.2} s, stale {stale:.2} s",
            o.ideal
        ));
    }
    Ok(format!(
        "rover {:.2} m/s, {:.2} rad/s, response {:.2} s; law {:?}; captured at {captured:.2} s (ideal {:.2} s); \
         target stale {stale:.2} s after capture; ArduPilot stopped {stop:.2} s and stood still {still:.2} s after the last setpoint",
        flown.measured.speed, flown.measured.turn_rate, flown.measured.response, flown.limits, o.ideal
    ))
}

/// The chase against the evader rover (the second outcome): captured no later than the ideal
/// Dubins pursuer + 3 s (both rovers start from rest), the setpoints' sign flipping at most 5
/// times.
fn check_rover_evader(flown: &Flown) -> Result<String, String> {
    let o = flown
        .outcomes
        .get(1)
        .ok_or("no chase against the evader rover")?;
    let captured = o.captured.ok_or("never captured")?;
    let line = format!(
        "{} vs {:?}, the evader a second SITL rover: captured at {captured:.2} s (ideal {:.2} s), {} sign flips",
        o.start.name, o.start.evader, o.ideal, o.flips
    );
    if captured > o.ideal + 3.0 || o.flips > 5 {
        return Err(line);
    }
    Ok(line)
}

/// Every frame of ArduPilot's stream taken or skipped whole, none dropped, by the unit and by
/// its replay on the host; the replay's setpoints are the unit's but for one per chase (at the
/// end of each, the unit's clock and the router's tell the target stale a few ms apart).
fn check_telemetry(flown: &Flown) -> Result<String, String> {
    let t = &flown.telemetry;
    let dropped = t.frames.bad_checksum + t.frames.bad_flags;
    let setpoints_apart = (t.endpoint.setpoints as usize).abs_diff(t.unit_setpoints);
    if dropped != 0
        || t.frames.skipped_bytes != 0
        || t.unit_bad_frames != Some(0.0)
        || setpoints_apart > flown.outcomes.len()
    {
        return Err(t.to_string());
    }
    Ok(format!(
        "{} frames parsed, {} skipped, 0 dropped; TC_BADFRM 0; {} setpoints; {}",
        t.frames.frames,
        t.frames.unknown,
        t.unit_setpoints,
        flown
            .cost
            .as_ref()
            .map_or("signed: no replay".to_string(), cost_line)
    ))
}

/// Signed both ways: ArduPilot ignores an unsigned request on the unit's link and answers a
/// signed one, signs every frame it sends there, and the unit refuses none of them; the chase
/// is checked as unsigned.
fn check_signed(flown: &Flown) -> Result<String, String> {
    let s = flown.signing.ok_or("the run was not signed")?;
    let chase = check_chase(flown)?;
    if s.unsigned_answered
        || !s.signed_answered
        || s.autopilot_frames.1 != 0
        || s.refusals != [Some(0.0); 3]
    {
        return Err(format!("{s}; {chase}"));
    }
    Ok(format!("{s}; {chase}"))
}
