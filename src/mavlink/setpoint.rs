//! The setpoint message for each vehicle kind TC_VEHICLE names, from the law's turn.
//!
//! - 0, ground vehicle: SET_ATTITUDE_TARGET, yaw rate and thrust used (type_mask 131);
//! - 1, fixed wing: attitude and thrust used (type_mask 7): the bank of the turn, pitch 0, yaw
//!   the heading, thrust 1;
//! - 2, ground vehicle by velocity (PX4 rovers): SET_POSITION_TARGET_LOCAL_NED, the velocity
//!   v_pm along the heading advanced by the turn over the guidance's period;
//! - 3, fixed wing by roll alone (ArduPlane): type_mask 198, the bank; pitch, yaw and throttle
//!   stay with the autopilot's energy controller;
//! - 4, fixed wing with the unit's energy hold (PX4 in offboard): type_mask 7, the bank, and
//!   pitch and throttle from [`super::energy`].
//!
//! A bank for turn rate omega at speed v is atan(v omega / (TC_BANK_EFF g)): an aircraft that
//! makes a share k of a coordinated turn's rate at a bank is asked the bank of omega / k.

use core::f32::consts::FRAC_PI_2;

use ::mavlink::dialects::common::{
    AttitudeTargetTypemask, MavFrame, PositionTargetTypemask, SET_ATTITUDE_TARGET_DATA,
    SET_POSITION_TARGET_LOCAL_NED_DATA,
};

use super::energy::Energy;
use crate::geodetic::bank_angle;

/// TC_VEHICLE's values (1, fixed wing, is the default of the attitude kinds).
pub const GROUND: u8 = 0;
pub const GROUND_BY_VELOCITY: u8 = 2;
pub const FIXED_WING_ROLL: u8 = 3;
pub const FIXED_WING_ENERGY: u8 = 4;

/// SET_ATTITUDE_TARGET's type_mask: yaw rate and thrust used (ground vehicles); attitude and
/// thrust used (fixed wing); the attitude's roll alone, pitch, yaw and throttle left to the
/// autopilot (ArduPlane reads bit 128 set with the roll rate's bit clear as "roll from the
/// quaternion").
const YAW_RATE_ONLY: u8 = 1 | 2 | 128;
const ATTITUDE_ONLY: u8 = 1 | 2 | 4;
const ROLL_ONLY: u8 = 2 | 4 | 64 | 128;
/// SET_POSITION_TARGET_LOCAL_NED's type_mask with the velocity used and position,
/// acceleration, yaw and yaw rate ignored (a PX4 rover in OFFBOARD).
const VELOCITY_ONLY: u16 = 1 | 2 | 4 | 64 | 128 | 256 | 1024 | 2048;

/// The law's turn for one setpoint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turn {
    /// v_pm, m/s.
    pub speed: f32,
    /// Turn rate, rad/s (clockwise from above positive).
    pub rate: f32,
    /// The pursuer's heading, rad (clockwise from north).
    pub heading: f32,
    /// The guidance's period, s: a velocity setpoint's course is advanced over it.
    pub period: f32,
}

/// The message for the autopilot.
#[derive(Clone, Debug, PartialEq)]
pub enum Setpoint {
    Attitude(SET_ATTITUDE_TARGET_DATA),
    Velocity(SET_POSITION_TARGET_LOCAL_NED_DATA),
}

/// Where a setpoint goes and when it was made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Address {
    pub system: u8,
    pub component: u8,
    /// time_boot_ms: our clock, ms.
    pub now_ms: u32,
}

/// The setpoint of `vehicle` (TC_VEHICLE) for `turn`; `efficiency` is TC_BANK_EFF, `energy`
/// the energy hold's pitch and throttle (TC_VEHICLE 4 only; level at full throttle without).
pub fn setpoint(
    vehicle: u8,
    turn: &Turn,
    efficiency: f32,
    energy: Option<Energy>,
    to: Address,
) -> Setpoint {
    if vehicle == GROUND_BY_VELOCITY {
        return Setpoint::Velocity(velocity(turn, to));
    }
    let mut message = SET_ATTITUDE_TARGET_DATA {
        time_boot_ms: to.now_ms,
        q: [1.0, 0.0, 0.0, 0.0],
        body_roll_rate: 0.0,
        body_pitch_rate: 0.0,
        body_yaw_rate: 0.0,
        thrust: 1.0,
        target_system: to.system,
        target_component: to.component,
        type_mask: AttitudeTargetTypemask::from_bits_retain(YAW_RATE_ONLY),
    };
    if vehicle == GROUND {
        message.body_yaw_rate = turn.rate;
        return Setpoint::Attitude(message);
    }
    let bank = bank_angle(turn.speed, turn.rate / efficiency);
    let (pitch, mask) = match vehicle {
        FIXED_WING_ROLL => (0.0, ROLL_ONLY),
        FIXED_WING_ENERGY => {
            let energy = energy.unwrap_or(Energy {
                pitch: 0.0,
                throttle: 1.0,
            });
            message.thrust = energy.throttle;
            (energy.pitch, ATTITUDE_ONLY)
        }
        _ => (0.0, ATTITUDE_ONLY),
    };
    message.q = quaternion(bank, pitch, turn.heading);
    message.type_mask = AttitudeTargetTypemask::from_bits_retain(mask);
    Setpoint::Attitude(message)
}

/// The velocity setpoint: its course the heading advanced by the turn over the guidance's
/// period (the span the sampled command is planned for), at most a quarter turn so that the
/// side of the turn is unambiguous.
fn velocity(turn: &Turn, to: Address) -> SET_POSITION_TARGET_LOCAL_NED_DATA {
    let advance = (turn.rate * turn.period).clamp(-FRAC_PI_2, FRAC_PI_2);
    let (sin, cos) = crate::num::f32_math::sin_cos(turn.heading + advance);
    SET_POSITION_TARGET_LOCAL_NED_DATA {
        time_boot_ms: to.now_ms,
        vx: turn.speed * cos,
        vy: turn.speed * sin,
        target_system: to.system,
        target_component: to.component,
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
        type_mask: PositionTargetTypemask::from_bits_retain(VELOCITY_ONLY),
        ..SET_POSITION_TARGET_LOCAL_NED_DATA::DEFAULT
    }
}

/// The attitude quaternion (w, x, y, z; body to north-east-down) of `roll`, `pitch` and `yaw`
/// (rad; Euler angles in yaw, pitch, roll order).
fn quaternion(roll: f32, pitch: f32, yaw: f32) -> [f32; 4] {
    use crate::num::Scalar;
    let (sr, cr) = Scalar::sin_cos(roll * 0.5);
    let (sp, cp) = Scalar::sin_cos(pitch * 0.5);
    let (sy, cy) = Scalar::sin_cos(yaw * 0.5);
    [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ]
}
