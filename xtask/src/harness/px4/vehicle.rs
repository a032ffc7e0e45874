//! The PX4 pursuer made ready and measured: its position and attitude streams raised on the
//! offboard link, a valid position awaited, OFFBOARD entered behind a stream of the ground
//! station's own velocity setpoints and armed; then its speed, its largest turn rate and its
//! heading's response driven out with velocity setpoints, as the unit will drive it.

use std::time::{Duration, Instant};

use mavlink::dialects::common::{
    MavCmd, MavFrame, PositionTargetTypemask, SET_POSITION_TARGET_LOCAL_NED_DATA,
};
use mavlink::MessageData;

use crate::harness::autopilot::chase::Outcome;
use crate::harness::autopilot::harness::{Harness, NoTarget, AUTOPILOT};
use crate::harness::autopilot::message::{command, STREAM_INTERVAL_US};
use crate::harness::autopilot::router::Source;
use crate::harness::autopilot::Measured;

/// PX4's OFFBOARD in HEARTBEAT's custom_mode: main mode 6 in bits 16 to 23.
pub const OFFBOARD: u32 = 6 << 16;
/// SET_POSITION_TARGET_LOCAL_NED's type_mask for a velocity alone (the unit's TC_VEHICLE 2).
pub const VELOCITY_ONLY: u16 = 3527;
/// GLOBAL_POSITION_INT's and ATTITUDE's message ids with their intervals (us): the streams
/// the unit and the harness read.
pub const STREAMS: [(f32, f32); 2] = [(33.0, STREAM_INTERVAL_US), (30.0, STREAM_INTERVAL_US)];
/// VFR_HUD's id: an aircraft's airspeed, at 10 Hz; off for a rover.
pub const VFR_HUD: f32 = 74.0;
/// The Onboard mode's other streams above 5 Hz (ODOMETRY, HIGHRES_IMU, ATTITUDE_QUATERNION,
/// LOCAL_POSITION_NED, SERVO_OUTPUT_RAW, GPS_RAW_INT, ALTITUDE, DISTANCE_SENSOR, TIMESYNC):
/// off, as a user configures the companion's link, so that the unit's UART carries what it
/// reads.
const QUIETED: [f32; 9] = [331.0, 105.0, 31.0, 32.0, 36.0, 24.0, 141.0, 132.0, 111.0];
/// MAV_CMD_SET_MESSAGE_INTERVAL's command number.
const SET_MESSAGE_INTERVAL: u32 = 511;

/// A velocity setpoint from the ground station: `speed` (m/s) along `course` (rad, clockwise
/// from north), in the local NED frame.
pub fn velocity(speed: f64, course: f64) -> SET_POSITION_TARGET_LOCAL_NED_DATA {
    SET_POSITION_TARGET_LOCAL_NED_DATA {
        vx: (speed * course.cos()) as f32,
        vy: (speed * course.sin()) as f32,
        type_mask: PositionTargetTypemask::from_bits_truncate(VELOCITY_ONLY),
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
        target_system: AUTOPILOT.0,
        target_component: AUTOPILOT.1,
        ..Default::default()
    }
}

/// Streams `setpoint(h)` at 20 Hz for `seconds` of the vehicle's time.
pub fn stream<M: MessageData>(
    h: &mut Harness,
    seconds: f64,
    setpoint: &mut dyn FnMut(&Harness) -> M,
) -> Result<(), String> {
    let end = h.now_ms() + (seconds * 1000.0) as u32;
    while h.now_ms() < end {
        let message = setpoint(h);
        h.router.send_to_autopilot(&message)?;
        let next = h.now_ms() + 50;
        if !h.pump_until(&mut NoTarget, Duration::from_secs(2), &mut |h| {
            h.now_ms() >= next
        })? {
            return Err("PX4's position stream stopped".to_string());
        }
    }
    Ok(())
}

/// Holds the vehicle still under OFFBOARD for `seconds`: a zero velocity at 20 Hz.
pub fn hold(h: &mut Harness, seconds: f64) -> Result<(), String> {
    stream(h, seconds, &mut |_| velocity(0.0, 0.0))
}

/// Waits for PX4's heartbeat (30 s at most), sets `streams` (id, interval in us) and turns the
/// Onboard mode's other fast streams off, and waits for a position (90 s at most); the
/// wall-clock seconds it took.
pub fn prepare(h: &mut Harness, streams: &[(f32, f32)]) -> Result<f64, String> {
    let start = Instant::now();
    if !h.pump_until(&mut NoTarget, Duration::from_secs(30), &mut |h| {
        h.mode.is_some()
    })? {
        return Err("no heartbeat from PX4 within 30 s".to_string());
    }
    let intervals = streams.iter().copied().chain(QUIETED.map(|id| (id, -1.0)));
    for (id, interval) in intervals {
        set_interval(h, id, interval)?;
    }
    let placed = |h: &Harness| h.position.as_ref().is_some_and(|p| p.lat != 0);
    if !h.pump_until(&mut NoTarget, Duration::from_secs(90), &mut |h| placed(h))? {
        return Err("PX4 gave no position within 90 s".to_string());
    }
    Ok(start.elapsed().as_secs_f64())
}

/// [`prepare`] with the rover's streams (VFR_HUD off too), then OFFBOARD and armed behind a
/// zero velocity.
pub fn make_ready(h: &mut Harness) -> Result<f64, String> {
    let start = Instant::now();
    prepare(h, &[STREAMS[0], STREAMS[1], (VFR_HUD, -1.0)])?;
    enter_offboard(h, &mut |h, s| hold(h, s))?;
    Ok(start.elapsed().as_secs_f64())
}

/// Asks for message `id` every `interval` us (-1: never) until PX4 accepts (5 tries).
fn set_interval(h: &mut Harness, id: f32, interval: f32) -> Result<(), String> {
    for _ in 0..5 {
        let from = h.acks.len();
        let params = [id, interval, 0.0, 0.0, 0.0, 0.0, 0.0];
        h.router
            .send_to_autopilot(&command(MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, params))?;
        let acked = |h: &Harness| {
            h.acks[from..]
                .iter()
                .any(|&(c, r)| c == SET_MESSAGE_INTERVAL && r == 0)
        };
        if h.pump_until(&mut NoTarget, Duration::from_millis(500), &mut |h| acked(h))? {
            return Ok(());
        }
    }
    Err(format!(
        "PX4 did not take message {id}'s interval {interval} us"
    ))
}

/// Streams `keep` (the vehicle's setpoint for that many seconds), asks for OFFBOARD and arming
/// until both hold (60 s at most).
pub fn enter_offboard(
    h: &mut Harness,
    keep: &mut dyn FnMut(&mut Harness, f64) -> Result<(), String>,
) -> Result<(), String> {
    let deadline = Instant::now() + Duration::from_secs(60);
    while !(h.armed && h.mode == Some(OFFBOARD)) {
        if Instant::now() > deadline {
            return Err(format!(
                "PX4 never armed in OFFBOARD (mode {:?}, armed {})",
                h.mode, h.armed
            ));
        }
        keep(h, 0.5)?;
        let offboard = [1.0, 6.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        h.router
            .send_to_autopilot(&command(MavCmd::MAV_CMD_DO_SET_MODE, offboard))?;
        let arm = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        h.router
            .send_to_autopilot(&command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, arm))?;
        keep(h, 0.5)?;
    }
    Ok(())
}

/// Drives at `speed` for 8 s on its heading, then steps the course 90 degrees right and holds
/// it 4 s, then turns hard each way (the course always 90 degrees off the heading) for 5 s;
/// the speed over the straight's last half, the smaller side's mean turn rate over the turns'
/// last halves, and the time the heading took to 63 % of the step. Then holds still for 3 s.
pub fn measure(h: &mut Harness, speed: f64) -> Result<Measured, String> {
    let heading = |h: &Harness| h.rover.map_or(0.0, |r| r.state[2]);
    let course = heading(h);
    let fixes = h.fixes.len();
    stream(h, 8.0, &mut |_| velocity(speed, course))?;
    let half = h.now_ms() - 4000;
    let speeds: Vec<f64> = h.fixes[fixes..]
        .iter()
        .filter(|f| f.time_ms >= half)
        .map(|f| f.speed)
        .collect();
    let speed_held = speeds.iter().sum::<f64>() / speeds.len().max(1) as f64;
    let (from, step_ms) = (heading(h), h.now_ms());
    let stepped = from + std::f64::consts::FRAC_PI_2;
    let fixes = h.fixes.len();
    stream(h, 4.0, &mut |_| velocity(speed, stepped))?;
    let response = h.fixes[fixes..]
        .iter()
        .find(|f| twocars_sim::kinematics::wrap_pi(f.state[2] - from) >= 0.63 * (stepped - from))
        .map_or(f64::NAN, |f| f64::from(f.time_ms - step_ms) / 1000.0);
    let mut rates = [0.0; 2];
    for (side, rate) in [1.0, -1.0].into_iter().zip(&mut rates) {
        let start = h.yaw_rates.len();
        stream(h, 5.0, &mut |h| {
            velocity(speed, heading(h) + side * std::f64::consts::FRAC_PI_2)
        })?;
        let settled = h.now_ms() - 2500;
        let v: Vec<f64> = h.yaw_rates[start..]
            .iter()
            .filter(|(t, _)| *t >= settled)
            .map(|(_, r)| f64::from(*r).abs())
            .collect();
        *rate = v.iter().sum::<f64>() / v.len().max(1) as f64;
    }
    hold(h, 3.0)?;
    let turn_rate = rates[0].min(rates[1]);
    Ok(Measured {
        speed: speed_held,
        turn_rate,
        radius: speed_held / turn_rate,
        response,
    })
}

/// What PX4 says when it leaves OFFBOARD for want of setpoints.
pub const STOP_TEXT: &str = "ailsafe";

/// Whether PX4 left OFFBOARD, or said "failsafe", between the chase's start (records from
/// `texts` and `modes` on) and its end.
pub fn left_offboard(h: &Harness, texts: usize, modes: usize, o: &Outcome) -> bool {
    let end_ms = o.end_ms;
    let said = h.texts[texts..]
        .iter()
        .any(|(t, s, text)| *t <= end_ms && *s == Source::Autopilot && text.contains(STOP_TEXT));
    let left = h.modes[modes..]
        .iter()
        .any(|&(t, mode)| t <= end_ms && mode != OFFBOARD);
    said || left
}
