//! The unit's own hold of a fixed wing's airspeed and height (TC_VEHICLE 4), for autopilots
//! whose attitude setpoint leaves pitch and throttle to the sender: PX4 in offboard takes
//! SET_ATTITUDE_TARGET's thrust as a direct throttle and has no energy controller behind it.
//!
//! Two loops, each a proportional term on a trim that integrates the loop's error, so that the
//! trims are learnt in flight rather than set:
//! - height: a flight-path angle demand gamma_d = (h_ref - h) / (5 s x v), within +-0.15 rad;
//!   pitch = pitch trim + gamma_d + (gamma_d - gamma), gamma = climb / v, within +-0.35 rad;
//! - airspeed: throttle = throttle trim + 2 (v_ref - v) / v_ref + gamma_d, within 0 to 1.
//!
//! The height held is the one the engagement starts at; `reset` forgets it (the trims stay).
//! Until the hold has flown, its throttle trim starts where the autopilot's throttle is
//! (`seed_throttle`, from VFR_HUD): taking over from another controller keeps the throttle the
//! aircraft was trimmed at instead of dropping to half.
//! How PX4 SITL's SIH airplane flies under it is in docs/px4.md.

/// How fast a height error is flown off, s.
const HEIGHT_TIME_S: f32 = 5.0;
/// The steepest flight path the loop asks for, rad.
const MAX_PATH_ANGLE: f32 = 0.15;
/// Pitch's limit either way, rad.
const MAX_PITCH: f32 = 0.35;
/// The pitch trim's limit either way, rad.
const MAX_PITCH_TRIM: f32 = 0.3;
/// The pitch trim's integration time, s.
const PITCH_TRIM_TIME_S: f32 = 3.0;
/// The throttle trim's integration time, s.
const THROTTLE_TRIM_TIME_S: f32 = 2.0;
/// Throttle per relative airspeed error.
const SPEED_GAIN: f32 = 2.0;
/// The throttle trim at the start: half, until the loop has learnt it.
const THROTTLE_START: f32 = 0.5;
/// Below this speed (m/s) the path angle is not computed from it.
const MIN_SPEED: f32 = 1.0;

/// The aircraft's state as the loops read it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flight {
    /// Height above home, m.
    pub height: f32,
    /// Climb rate, m/s (up positive).
    pub climb: f32,
    /// Airspeed, m/s (the ground speed where the autopilot sends none).
    pub airspeed: f32,
}

/// Pitch (rad, nose up positive) and throttle (0 to 1) for one setpoint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Energy {
    /// rad, nose up positive.
    pub pitch: f32,
    /// 0 to 1.
    pub throttle: f32,
}

/// The loops' memory: the height held, the two trims, and whether it has flown yet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyHold {
    height: Option<f32>,
    pitch_trim: f32,
    throttle_trim: f32,
    flown: bool,
}

impl Default for EnergyHold {
    fn default() -> Self {
        Self::new()
    }
}

impl EnergyHold {
    /// No height held yet; the trims at level pitch and half throttle.
    pub const fn new() -> Self {
        EnergyHold {
            height: None,
            pitch_trim: 0.0,
            throttle_trim: THROTTLE_START,
            flown: false,
        }
    }

    /// Starts the throttle trim at `throttle` (0 to 1: the autopilot's throttle now) while the
    /// hold has not flown; after its first command the trim it learns stays. A value outside
    /// 0 to 1 (NaN included) is ignored.
    pub fn seed_throttle(&mut self, throttle: f32) {
        if !self.flown && (0.0..=1.0).contains(&throttle) {
            self.throttle_trim = throttle;
        }
    }

    /// Forgets the height held: the next engagement holds the one it starts at.
    pub fn reset(&mut self) {
        self.height = None;
    }

    /// The height held, m, once a command has set it.
    pub fn height(&self) -> Option<f32> {
        self.height
    }

    /// Pitch and throttle for `flight` at airspeed `airspeed_ref` (m/s), `dt` (s) after the
    /// last command. Non-finite input leaves the memory as it was and gives level pitch at the
    /// throttle trim.
    pub fn command(&mut self, flight: Flight, airspeed_ref: f32, dt: f32) -> Energy {
        let Flight {
            height,
            climb,
            airspeed,
        } = flight;
        let finite = [height, climb, airspeed, airspeed_ref, dt]
            .iter()
            .all(|v| v.is_finite());
        if !finite || airspeed_ref < MIN_SPEED || dt < 0.0 {
            return Energy {
                pitch: 0.0,
                throttle: self.throttle_trim,
            };
        }
        self.flown = true;
        let held = *self.height.get_or_insert(height);
        let speed = airspeed.max(MIN_SPEED);
        let demand = clamp((held - height) / (HEIGHT_TIME_S * speed), MAX_PATH_ANGLE);
        let path = climb / speed;
        self.pitch_trim = clamp(
            self.pitch_trim + dt * (demand - path) / PITCH_TRIM_TIME_S,
            MAX_PITCH_TRIM,
        );
        let pitch = clamp(self.pitch_trim + demand + (demand - path), MAX_PITCH);
        let error = (airspeed_ref - airspeed) / airspeed_ref;
        self.throttle_trim = unit(self.throttle_trim + dt * error / THROTTLE_TRIM_TIME_S);
        let throttle = unit(self.throttle_trim + SPEED_GAIN * error + demand);
        Energy { pitch, throttle }
    }
}

/// `x` within +-`limit` (a positive constant).
#[inline(always)]
fn clamp(x: f32, limit: f32) -> f32 {
    x.clamp(-limit, limit)
}

/// `x` within 0 to 1.
fn unit(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}
