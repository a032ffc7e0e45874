//! The pursuer's autopilot made ready and measured: WP_SPEED, the position and attitude streams,
//! GPS and EKF awaited, GUIDED and armed; then its top speed and its largest turn rate driven
//! out with the ground station's own SET_ATTITUDE_TARGET.

use std::time::{Duration, Instant};

use mavlink::dialects::common::{MavCmd, HEARTBEAT_DATA, SET_ATTITUDE_TARGET_DATA};
use mavlink::MessageData;

use crate::harness::autopilot::harness::wait_stopped;
use crate::harness::autopilot::harness::{Harness, NoTarget, AUTOPILOT};
use crate::harness::autopilot::message::{command, param_set, STREAM_INTERVAL_US};
use crate::harness::autopilot::router::Source;
use crate::harness::autopilot::Measured;

/// Rover's GUIDED mode number.
pub const GUIDED: u32 = 15;

/// SET_ATTITUDE_TARGET's type_mask for a yaw rate and thrust (the unit's, for ground vehicles).
pub const YAW_RATE_AND_THRUST: u8 = 1 | 2 | 128;
/// GLOBAL_POSITION_INT's and ATTITUDE's message ids.
const GLOBAL_POSITION_INT: f32 = 33.0;
const ATTITUDE: f32 = 30.0;
/// SITL's speed-up while the EKF starts, and the rover's after it. The start is a wait on the
/// simulated clock (GPS lock, then the EKF's checks: about 40 s at 1x), and ArduPilot takes
/// SIM_SPEEDUP at run time (MAVProxy's sitl_autospeedup module uses it so). The unit's link
/// carries the heartbeat alone meanwhile, so that its emulator has nothing to fall behind on.
const START_SPEEDUP: f32 = 8.0;
const RUN_SPEEDUP: f32 = 1.0;

/// Sets `name` on the autopilot and waits (5 s) for its PARAM_VALUE to say `value`.
pub fn set_autopilot_param(h: &mut Harness, name: &str, value: f32) -> Result<(), String> {
    let from = h.params.len();
    h.router
        .send_to_autopilot(&param_set(AUTOPILOT, name, value))?;
    let echoed = |h: &Harness| {
        h.params[from..]
            .iter()
            .any(|(s, n, v)| *s == Source::Autopilot && n == name && *v == value)
    };
    if h.pump_until(&mut NoTarget, Duration::from_secs(5), &mut |h| echoed(h))? {
        Ok(())
    } else {
        Err(format!("ArduPilot did not take {name} = {value}"))
    }
}

/// How long the set-up took, s (wall clock): GPS and EKF, then GUIDED and armed.
pub struct Ready {
    pub ekf_s: f64,
    pub armed_s: f64,
}

/// Waits for the autopilot's heartbeat, sets WP_SPEED (the speed at thrust 1, m/s), raises the
/// position and attitude streams to 20 Hz, waits for the EKF to use GPS at [`START_SPEEDUP`]
/// (120 s at most), then at 1x asks for GUIDED and arming until both hold (60 s at most).
pub fn make_ready(h: &mut Harness, wp_speed: f32) -> Result<Ready, String> {
    let start = Instant::now();
    if !h.pump_until(&mut NoTarget, Duration::from_secs(20), &mut |h| {
        h.mode.is_some()
    })? {
        return Err("no heartbeat from ArduPilot".to_string());
    }
    set_autopilot_param(h, "WP_SPEED", wp_speed)?;
    for id in [GLOBAL_POSITION_INT, ATTITUDE] {
        let interval = [id, STREAM_INTERVAL_US, 0.0, 0.0, 0.0, 0.0, 0.0];
        h.router
            .send_to_autopilot(&command(MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, interval))?;
    }
    h.router.pass_to_unit(Some(&[HEARTBEAT_DATA::ID]));
    set_autopilot_param(h, "SIM_SPEEDUP", START_SPEEDUP)?;
    let using_gps = |h: &Harness| h.text_since(0, Source::Autopilot, "is using GPS").is_some();
    if !h.pump_until(&mut NoTarget, Duration::from_secs(120), &mut |h| {
        using_gps(h)
    })? {
        return Err("ArduPilot's EKF never used GPS (120 s)".to_string());
    }
    set_autopilot_param(h, "SIM_SPEEDUP", RUN_SPEEDUP)?;
    h.router.pass_to_unit(None);
    let ekf_s = start.elapsed().as_secs_f64();
    switch_mode(h, GUIDED, true, Duration::from_secs(60))?;
    Ok(Ready {
        ekf_s,
        armed_s: start.elapsed().as_secs_f64(),
    })
}

/// Asks for `mode` (and arming, with `arm`) once a second until the heartbeat shows both,
/// `within` of wall clock at most.
pub fn switch_mode(h: &mut Harness, mode: u32, arm: bool, within: Duration) -> Result<(), String> {
    let deadline = Instant::now() + within;
    while !(h.mode == Some(mode) && (h.armed || !arm)) {
        if Instant::now() > deadline {
            return Err(format!(
                "ArduPilot never took mode {mode} (mode {:?}, armed {})",
                h.mode, h.armed
            ));
        }
        let set = [1.0, mode as f32, 0.0, 0.0, 0.0, 0.0, 0.0];
        h.router
            .send_to_autopilot(&command(MavCmd::MAV_CMD_DO_SET_MODE, set))?;
        if arm {
            let arm = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
            h.router
                .send_to_autopilot(&command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, arm))?;
        }
        h.pump_until(&mut NoTarget, Duration::from_secs(1), &mut |h| {
            h.mode == Some(mode) && (h.armed || !arm)
        })?;
    }
    Ok(())
}

/// Sends `setpoint` to the autopilot every 50 ms of its clock until `end_ms`.
pub fn send_until(
    h: &mut Harness,
    setpoint: &SET_ATTITUDE_TARGET_DATA,
    end_ms: u32,
) -> Result<(), String> {
    while h.now_ms() < end_ms {
        h.router.send_to_autopilot(setpoint)?;
        let next = h.now_ms() + 50;
        h.pump_until(&mut NoTarget, Duration::from_secs(2), &mut |h| {
            h.now_ms() >= next
        })?;
    }
    Ok(())
}

/// The ground station's setpoint (yaw rate, thrust 1) at 20 Hz for `seconds` of the rover's
/// time; the rover's mean speed and yaw rate over the second half, and the time its yaw rate
/// took to reach 63 % of that mean.
fn drive(h: &mut Harness, yaw_rate: f32, seconds: f64) -> Result<(f64, f64, f64), String> {
    let setpoint = SET_ATTITUDE_TARGET_DATA {
        time_boot_ms: 0,
        q: [1.0, 0.0, 0.0, 0.0],
        body_roll_rate: 0.0,
        body_pitch_rate: 0.0,
        body_yaw_rate: yaw_rate,
        thrust: 1.0,
        target_system: AUTOPILOT.0,
        target_component: AUTOPILOT.1,
        type_mask: mavlink::dialects::common::AttitudeTargetTypemask::from_bits_truncate(
            YAW_RATE_AND_THRUST,
        ),
    };
    let start = h.now_ms();
    let end = start + (seconds * 1000.0) as u32;
    let half = start + (seconds * 500.0) as u32;
    let (fixes, rates) = (h.fixes.len(), h.yaw_rates.len());
    send_until(h, &setpoint, end)?;
    let mean = |v: Vec<f64>| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let speed = mean(
        h.fixes[fixes..]
            .iter()
            .filter(|f| f.time_ms >= half)
            .map(|f| f.speed)
            .collect(),
    );
    let rate = mean(
        h.yaw_rates[rates..]
            .iter()
            .filter(|(t, _)| *t >= half)
            .map(|(_, r)| f64::from(*r))
            .collect(),
    );
    let response = h.yaw_rates[rates..]
        .iter()
        .find(|(_, r)| f64::from(*r) * rate.signum() >= 0.63 * rate.abs())
        .map_or(f64::NAN, |(t, _)| f64::from(t.wrapping_sub(start)) / 1000.0);
    Ok((speed, rate, response))
}

/// Drives straight for 12 s (its speed overshoots for the first few), then hard left and hard
/// right (asking 3 rad/s, more than the rover can), 6 s each; then lets the rover stop (its 3 s
/// setpoint timeout, then braking).
pub fn measure(h: &mut Harness) -> Result<Measured, String> {
    let (speed, _, _) = drive(h, 0.0, 12.0)?;
    let (_, left, response) = drive(h, -3.0, 6.0)?;
    let (_, right, _) = drive(h, 3.0, 6.0)?;
    let turn_rate = left.abs().min(right.abs());
    wait_stopped(h, &mut NoTarget, 15.0)?;
    Ok(Measured {
        speed,
        turn_rate,
        radius: speed / turn_rate,
        response,
    })
}
