//! ArduPlane as the pursuer: made ready (streams, GPS and EKF, TAKEOFF mode to its height, then
//! GUIDED) and measured under the unit's own kind of setpoint, SET_ATTITUDE_TARGET with the
//! roll alone (type_mask 198), which leaves airspeed and height to ArduPlane's energy
//! controller (TECS).

use std::time::{Duration, Instant};

use mavlink::dialects::common::{AttitudeTargetTypemask, MavCmd, SET_ATTITUDE_TARGET_DATA};

use super::vehicle::{send_until, set_autopilot_param, switch_mode, GUIDED};
use crate::harness::autopilot::aircraft::{efficiency, read_step, StepMarks};
use crate::harness::autopilot::harness::{Harness, NoTarget, AUTOPILOT};
use crate::harness::autopilot::message::{command, STREAM_INTERVAL_US};
use crate::harness::autopilot::router::Source;

/// ArduPlane's TAKEOFF mode: climbs to TKOFF_ALT on its own, then loiters.
const TAKEOFF: u32 = 13;
/// The height the plane climbs to before a chase, m above home.
pub const HEIGHT: f32 = 100.0;
/// SET_ATTITUDE_TARGET's type_mask with the roll alone used (the unit's TC_VEHICLE 3).
pub const ROLL_ONLY: u8 = 2 | 4 | 64 | 128;
/// The bank the turn is measured at, deg: well inside ROLL_LIMIT_DEG (65) and stall
/// prevention's limit at cruise, so that the law's turns leave the roll controller room.
pub const MEASURED_BANK_DEG: f64 = 45.0;
/// The message ids the set-up raises, with their intervals (us): position and attitude at the
/// unit's rate, VFR_HUD (airspeed) and NAV_CONTROLLER_OUTPUT (nav roll) at 10 Hz.
const STREAMS: [(f32, f32); 4] = [
    (33.0, STREAM_INTERVAL_US),
    (30.0, STREAM_INTERVAL_US),
    (74.0, 100_000.0),
    (62.0, 100_000.0),
];

/// The aircraft as flown under roll setpoints.
#[derive(Clone, Copy, Debug)]
pub struct Flown {
    /// Ground speed straight and level, m/s (no wind: the true airspeed).
    pub speed: f64,
    /// VFR_HUD airspeed straight and level, m/s.
    pub airspeed: f64,
    /// The steady turn's curvature at the bank measured, the smaller side's, 1/m.
    pub curvature: f64,
    /// The share of a coordinated turn's rate that curvature is: k in omega = k g tan(phi) / v.
    pub efficiency: f64,
    /// The roll's response to a step from level to the measured bank: time to 63 %, s.
    pub response: f64,
}

impl Flown {
    /// The aircraft as measured at `bank_deg`, in a line.
    pub fn line(&self, bank_deg: f64) -> String {
        format!(
        "{:.2} m/s ground speed level, airspeed {:.2} m/s; at {bank_deg} deg of bank curvature {:.5} 1/m (radius {:.1} m), {:.0} % of a coordinated turn's; roll response {:.2} s",
            self.speed,
            self.airspeed,
            self.curvature,
        1.0 / self.curvature,
        100.0 * self.efficiency,
            self.response
        )
    }
}

/// Waits for the heartbeat, raises the streams, waits for the EKF to use GPS (120 s), takes off
/// in TAKEOFF mode to `height` (m above home; 120 s), then switches to GUIDED; the wall-clock
/// seconds it took.
pub fn make_ready(h: &mut Harness, height: f32) -> Result<f64, String> {
    let start = Instant::now();
    if !h.pump_until(&mut NoTarget, Duration::from_secs(20), &mut |h| {
        h.mode.is_some()
    })? {
        return Err("no heartbeat from ArduPlane".to_string());
    }
    for (id, interval) in STREAMS {
        let params = [id, interval, 0.0, 0.0, 0.0, 0.0, 0.0];
        h.router
            .send_to_autopilot(&command(MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, params))?;
    }
    set_autopilot_param(h, "TKOFF_ALT", height)?;
    let using_gps = |h: &Harness| h.text_since(0, Source::Autopilot, "is using GPS").is_some();
    if !h.pump_until(&mut NoTarget, Duration::from_secs(120), &mut |h| {
        using_gps(h)
    })? {
        return Err("ArduPlane's EKF never used GPS (120 s)".to_string());
    }
    switch_mode(h, TAKEOFF, true, Duration::from_secs(60))?;
    let high = |h: &Harness| h.rover.is_some_and(|r| r.height > 0.9 * f64::from(height));
    if !h.pump_until(&mut NoTarget, Duration::from_secs(120), &mut |h| high(h))? {
        return Err(format!("ArduPlane never climbed to {height} m (120 s)"));
    }
    switch_mode(h, GUIDED, false, Duration::from_secs(20))?;
    Ok(start.elapsed().as_secs_f64())
}

/// What one roll step showed over its second half: mean ground speed, mean airspeed, heading
/// rate (rad/s, clockwise) and the roll's time to 63 % of the step (s).
struct Step {
    speed: f64,
    airspeed: f64,
    rate: f64,
    response: f64,
}

/// GUIDED's roll-only setpoint (type_mask [`ROLL_ONLY`]) for a bank of `bank` (rad, right
/// wing down positive).
pub fn roll_setpoint(bank: f64) -> SET_ATTITUDE_TARGET_DATA {
    let half_angle = bank as f32 / 2.0;
    SET_ATTITUDE_TARGET_DATA {
        q: [half_angle.cos(), half_angle.sin(), 0.0, 0.0],
        target_system: AUTOPILOT.0,
        target_component: AUTOPILOT.1,
        type_mask: AttitudeTargetTypemask::from_bits_truncate(ROLL_ONLY),
        ..Default::default()
    }
}

/// The roll setpoint `bank_deg` at 20 Hz for `seconds` of the aircraft's time.
fn roll(h: &mut Harness, bank_deg: f64, seconds: f64) -> Result<Step, String> {
    let setpoint = roll_setpoint(bank_deg.to_radians());
    let marks = StepMarks::now(h);
    let end = h.now_ms() + (seconds * 1000.0) as u32;
    let half = h.now_ms() + (seconds * 500.0) as u32;
    let airspeeds = h.airspeeds.len();
    send_until(h, &setpoint, end)?;
    let (speed, rate, response) = read_step(h, marks, bank_deg, seconds);
    let settled: Vec<f64> = h.airspeeds[airspeeds..]
        .iter()
        .filter(|(t, _)| *t >= half)
        .map(|(_, v)| f64::from(*v))
        .collect();
    Ok(Step {
        speed,
        airspeed: settled.iter().sum::<f64>() / settled.len().max(1) as f64,
        rate,
        response,
    })
}

/// Level for 12 s, then `bank_deg` right and left, 12 s each, then level again.
pub fn measure(h: &mut Harness, bank_deg: f64) -> Result<Flown, String> {
    let level = roll(h, 0.0, 12.0)?;
    let right = roll(h, bank_deg, 12.0)?;
    let left = roll(h, -bank_deg, 12.0)?;
    roll(h, 0.0, 6.0)?;
    let curvature = (right.rate / right.speed)
        .abs()
        .min((left.rate / left.speed).abs());
    Ok(Flown {
        speed: level.speed,
        airspeed: level.airspeed,
        curvature,
        efficiency: efficiency(curvature, bank_deg, level.speed),
        response: right.response,
    })
}
