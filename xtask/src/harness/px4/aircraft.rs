//! The PX4 airplane (SIH) as the pursuer: taken off and flown by the ground station's own
//! SET_ATTITUDE_TARGET in OFFBOARD (type_mask 7, the unit's TC_VEHICLE 4), its pitch and
//! throttle from the unit's energy hold (`twocars::mavlink::energy`), and measured under it.

use std::time::Duration;

use mavlink::dialects::common::{AttitudeTargetTypemask, SET_ATTITUDE_TARGET_DATA};
use twocars::mavlink::energy::{Energy, EnergyHold, Flight};

use super::vehicle::{enter_offboard, prepare, stream, STREAMS, VFR_HUD};
use crate::harness::autopilot::aircraft::{efficiency, read_step, StepMarks};
use crate::harness::autopilot::harness::{Harness, AUTOPILOT};

/// The airspeed held against the simulated evader, m/s: the SIH airplane's throttle is 0.65
/// there, with room either way.
pub const AIRSPEED: f32 = 10.0;

/// The ground station's energy hold and the airspeed it keeps (m/s).
pub struct Held {
    pub hold: EnergyHold,
    pub airspeed: f32,
}

impl Held {
    pub fn new(airspeed: f32) -> Held {
        Held {
            hold: EnergyHold::new(),
            airspeed,
        }
    }
}
/// The height the climb ends at, m above home.
const CLIMB_TO_M: f64 = 40.0;
/// The bank the turn is measured at, deg (PX4's FW_R_LIM is 50).
pub const MEASURED_BANK_DEG: f64 = 45.0;
/// SET_ATTITUDE_TARGET's type_mask with the attitude and thrust used.
const ATTITUDE_AND_THRUST: u8 = 1 | 2 | 4;

/// The aircraft as flown.
#[derive(Clone, Copy, Debug)]
pub struct Flown {
    /// Ground speed level at the airspeed held, m/s.
    pub speed: f64,
    /// Curvature at [`MEASURED_BANK_DEG`], the smaller side's, 1/m.
    pub curvature: f64,
    /// The share of a coordinated turn's rate that curvature is.
    pub efficiency: f64,
    /// The roll's time to 63 % of a step from level to the measured bank, s.
    pub response: f64,
}

/// The ground station's attitude setpoint: `roll`, `pitch` (rad), yaw the heading, `thrust`.
fn attitude(h: &Harness, roll: f64, pitch: f64, thrust: f32) -> SET_ATTITUDE_TARGET_DATA {
    let yaw = h.rover.map_or(0.0, |r| r.state[2]);
    let (sr, cr) = (roll / 2.0).sin_cos();
    let (sp, cp) = (pitch / 2.0).sin_cos();
    let (sy, cy) = (yaw / 2.0).sin_cos();
    let q = [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ];
    SET_ATTITUDE_TARGET_DATA {
        q: q.map(|v| v as f32),
        thrust,
        target_system: AUTOPILOT.0,
        target_component: AUTOPILOT.1,
        type_mask: AttitudeTargetTypemask::from_bits_truncate(ATTITUDE_AND_THRUST),
        ..Default::default()
    }
}

/// The energy hold's command on the aircraft's last fix and airspeed.
fn hold_energy(h: &Harness, held: &mut Held) -> Energy {
    let Some(p) = h.position.as_ref() else {
        return Energy {
            pitch: 0.0,
            throttle: 0.5,
        };
    };
    let ground = f32::from(p.vx).hypot(f32::from(p.vy)) / 100.0;
    let flight = Flight {
        height: p.relative_alt as f32 / 1000.0,
        climb: -f32::from(p.vz) / 100.0,
        airspeed: h.airspeeds.last().map_or(ground, |(_, v)| *v),
    };
    held.hold.command(flight, held.airspeed, 0.05)
}

/// Flies `bank_deg` for `seconds` of the aircraft's time, pitch and throttle from `held`.
pub fn fly_level(
    h: &mut Harness,
    held: &mut Held,
    bank_deg: f64,
    seconds: f64,
) -> Result<(), String> {
    stream(h, seconds, &mut |h| banked(h, held, bank_deg.to_radians()))
}

/// The attitude setpoint for `bank` (rad), pitch and throttle from `held`.
pub fn banked(h: &Harness, held: &mut Held, bank: f64) -> SET_ATTITUDE_TARGET_DATA {
    let e = hold_energy(h, held);
    attitude(h, bank, f64::from(e.pitch), e.throttle)
}

/// Streams, a position, then OFFBOARD and armed behind a climb-out (pitch 12 degrees,
/// throttle 0.9) to [`CLIMB_TO_M`]; the wall-clock seconds it took.
pub fn make_ready(h: &mut Harness) -> Result<f64, String> {
    let start = std::time::Instant::now();
    prepare(h, &[STREAMS[0], STREAMS[1], (VFR_HUD, 100_000.0)])?;
    let climb = |h: &mut Harness, seconds: f64| {
        stream(h, seconds, &mut |h| {
            attitude(h, 0.0, 12f64.to_radians(), 0.9)
        })
    };
    enter_offboard(h, &mut |h, s| climb(h, s))?;
    let high = |h: &Harness| h.rover.is_some_and(|r| r.height > CLIMB_TO_M);
    let deadline = std::time::Instant::now() + Duration::from_secs(60);
    while !high(h) {
        if std::time::Instant::now() > deadline {
            return Err(format!(
                "the airplane never climbed to {CLIMB_TO_M} m (60 s)"
            ));
        }
        climb(h, 0.5)?;
    }
    Ok(start.elapsed().as_secs_f64())
}

/// Back in OFFBOARD (after a failsafe) behind level flight under `held`.
pub fn reenter_offboard(h: &mut Harness, held: &mut Held) -> Result<(), String> {
    enter_offboard(h, &mut |h, s| fly_level(h, held, 0.0, s))
}

/// Level for 20 s (the climb-out settles), then [`MEASURED_BANK_DEG`] right and left, 12 s
/// each, then level 6 s; each step's second half averaged.
pub fn measure(h: &mut Harness, held: &mut Held) -> Result<Flown, String> {
    let mut step = |h: &mut Harness, bank: f64, seconds: f64| {
        let marks = StepMarks::now(h);
        fly_level(h, held, bank, seconds)?;
        Ok::<_, String>(read_step(h, marks, bank, seconds))
    };
    let (speed, _, _) = step(h, 0.0, 20.0)?;
    let (right_speed, right, response) = step(h, MEASURED_BANK_DEG, 12.0)?;
    let (left_speed, left, _) = step(h, -MEASURED_BANK_DEG, 12.0)?;
    step(h, 0.0, 6.0)?;
    let curvature = (right / right_speed).abs().min((left / left_speed).abs());
    Ok(Flown {
        speed,
        curvature,
        efficiency: efficiency(curvature, MEASURED_BANK_DEG, speed),
        response,
    })
}
