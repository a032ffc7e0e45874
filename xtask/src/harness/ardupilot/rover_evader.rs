//! The evader a second ArduPilot Rover SITL (`cargo xtask run --autopilot ardupilot --rover-evader`):
//! for each chase an instance started where the start puts it, at rest, made ready as the
//! pursuer is (GUIDED, armed, its position stream at 20 Hz), and driven by an evader of the
//! adversary suite through its own GUIDED SET_ATTITUDE_TARGET on the ground station's link.
//! Its own GLOBAL_POSITION_INT, its own clock's `time_boot_ms` included, is the unit's target
//! (re-sent from system 2, TC_TGT_SYSID, since both instances call themselves system 1).

use std::path::Path;
use std::time::Duration;

use mavlink::dialects::common::{AttitudeTargetTypemask, SET_ATTITUDE_TARGET_DATA};
use twocars_sim::autopilot::{Plane, HOME};

use super::sitl::{Frame, Launch, Sitl};
use super::vehicle::{make_ready, YAW_RATE_AND_THRUST};
use crate::harness::autopilot::chase::{place, Outcome, Start};
use crate::harness::autopilot::evader::{self, Steer, Terms};
use crate::harness::autopilot::harness::{Harness, NoTarget, AUTOPILOT};
use crate::harness::autopilot::router::Router;

/// The evader's SITL instance (TCP 5770): the pursuer is instance 0.
const INSTANCE: u16 = 1;
/// Thrust per m/s of the evader's speed error, in units of its speed at thrust 1: its speed
/// held near the strategy's (at most v_em).
const SPEED_GAIN: f64 = 1.0;

/// The evader's rover: its SITL process and the ground station's link to it.
pub struct EvaderRover {
    _sitl: Sitl,
    harness: Harness,
}

/// Starts the evader's instance at `state` (north, east, heading clockwise from north, in the
/// plane about home), its speed at thrust 1 `wp_speed` (m/s), and makes it ready; while it
/// starts, `keep` holds the pursuer (reading its link, so that no buffer fills; streaming
/// what its mode needs).
pub fn launch(
    binary: &Path,
    pursuer: &mut Harness,
    keep: &mut dyn FnMut(&mut Harness) -> Result<(), String>,
    state: [f64; 3],
    wp_speed: f32,
) -> Result<EvaderRover, String> {
    let (lat, lon) = Plane::new(HOME).fix(state[0], state[1]);
    let home = (f64::from(lat) * 1e-7, f64::from(lon) * 1e-7);
    let heading = state[2].to_degrees().rem_euclid(360.0);
    let binary = binary.to_path_buf();
    let starting = std::thread::spawn(move || -> Result<EvaderRover, String> {
        let launch = Launch {
            frame: Frame::Rover,
            instance: INSTANCE,
            home,
            heading,
            speedup: 1,
        };
        let (sitl, serial0) = Sitl::start(&binary, launch)?;
        let mut harness = Harness::new(Router::alone(serial0)?, HOME, 0);
        make_ready(&mut harness, wp_speed)?;
        Ok(EvaderRover {
            _sitl: sitl,
            harness,
        })
    });
    while !starting.is_finished() {
        keep(pursuer)?;
    }
    starting
        .join()
        .map_err(|_| "the evader's start panicked".to_string())?
}

/// The evader's rover told its strategy's turn as a GUIDED yaw rate and thrust.
pub(super) struct RoverSteer {
    /// The evader's speed at thrust 1, m/s.
    pub wp_speed: f64,
}

impl Steer for RoverSteer {
    /// The thrust corrects the speed by [`SPEED_GAIN`]: WP_SPEED alone sets the rover's
    /// cruise, and it overshoots it by a quarter after each start and turn.
    fn steer(&mut self, h: &mut Harness, w: f64, speed: f64, measured: f64) -> Result<(), String> {
        let asked = if speed > 0.0 {
            speed + SPEED_GAIN * (speed - measured)
        } else {
            0.0
        };
        let setpoint = SET_ATTITUDE_TARGET_DATA {
            time_boot_ms: 0,
            q: [1.0, 0.0, 0.0, 0.0],
            body_roll_rate: 0.0,
            body_pitch_rate: 0.0,
            body_yaw_rate: (speed * w) as f32,
            thrust: (asked / self.wp_speed).clamp(0.0, 1.0) as f32,
            target_system: AUTOPILOT.0,
            target_component: AUTOPILOT.1,
            type_mask: AttitudeTargetTypemask::from_bits_truncate(YAW_RATE_AND_THRUST),
        };
        h.router.send_to_autopilot(&setpoint)
    }
}

/// Reads the pursuer's link for 200 ms: what an ArduPilot rover standing in GUIDED needs.
pub fn pump(h: &mut Harness) -> Result<(), String> {
    h.pump_until(&mut NoTarget, Duration::from_millis(200), &mut |_| false)
        .map(|_| ())
}

/// Flies `start` with the evader a rover of its own: launched at the start, at rest (the
/// pursuer held by `keep` meanwhile), driven by `start.evader` within `limits`; the evader's
/// peak and mean speed over the chase (m/s) beside the outcome.
pub fn fly(
    h: &mut Harness,
    keep: &mut dyn FnMut(&mut Harness) -> Result<(), String>,
    binary: &Path,
    start: Start,
    limits: [f64; 4],
    terms: Terms,
) -> Result<(Outcome, [f64; 2]), String> {
    let placed = place(h.rover.ok_or("no fix from the rover")?.state, &start);
    let wp_speed = limits[2];
    let mut evader = launch(binary, h, keep, placed, wp_speed as f32)?;
    let mut steer = RoverSteer { wp_speed };
    evader::chase(h, &mut evader.harness, &mut steer, start, limits, terms)
}
