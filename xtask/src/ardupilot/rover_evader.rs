//! The evader a second ArduPilot Rover SITL (`cargo xtask run --link ardupilot --rover-evader`):
//! for each chase an instance started where the start puts it, at rest, made ready as the
//! pursuer is (GUIDED, armed, its position stream at 20 Hz), and driven by an evader of the
//! adversary suite through its own GUIDED SET_ATTITUDE_TARGET on the ground station's link.
//! Its own GLOBAL_POSITION_INT, its own clock's `time_boot_ms` included, is the unit's target
//! (re-sent from system 2, TC_TGT_SYSID, since both instances call themselves system 1).

use std::path::Path;
use std::time::Duration;

use host_tests::adversary::{Adversary, Opponent};
use host_tests::autopilot::{Plane, HOME};
use host_tests::kinematics::distance;
use mavlink::dialects::common::{
    AttitudeTargetTypemask, GLOBAL_POSITION_INT_DATA, SET_ATTITUDE_TARGET_DATA,
};

use super::sitl::{Frame, Launch, Sitl};
use super::vehicle::{make_ready, YAW_RATE_AND_THRUST};
use crate::autopilot::chase::{chase_params, place, pursue, Began, Outcome, Start};
use crate::autopilot::harness::{Harness, Injector, NoTarget, RoverFix, AUTOPILOT};
use crate::autopilot::router::Router;

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
/// starts, `pursuer` keeps forwarding (so no link's buffer fills).
pub fn launch(
    binary: &Path,
    pursuer: &mut Harness,
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
        pursuer.pump_until(&mut NoTarget, Duration::from_millis(200), &mut |_| false)?;
    }
    starting
        .join()
        .map_err(|_| "the evader's start panicked".to_string())?
}

/// The evader's rover as the unit's target: on each of the pursuer's fixes the evader's link
/// is read, capture judged on both rovers' fixes, and on each new evader fix its strategy's
/// command sent and the fix handed on.
struct RoverTarget<'a> {
    evader: &'a mut Harness,
    adversary: Adversary,
    /// The evader's speed at thrust 1, m/s.
    wp_speed: f64,
    start_ms: u32,
    eps: f64,
    t_max: f64,
    last_fix_ms: Option<u32>,
    captured_ms: Option<u32>,
    on: bool,
}

impl RoverTarget<'_> {
    /// The evader's yaw rate (rad/s, clockwise) and thrust for its strategy's curvature `w`
    /// (1/m, clockwise in the plane) at `speed` (m/s), the rover going at `measured` (m/s).
    /// The thrust corrects the speed by [`SPEED_GAIN`]: WP_SPEED alone sets the rover's cruise,
    /// and it overshoots it by a quarter after each start and turn.
    fn steer(&mut self, w: f64, speed: f64, measured: f64) -> Result<(), String> {
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
        self.evader.router.send_to_autopilot(&setpoint)
    }

    fn step(&mut self, rover: &RoverFix) -> Result<Option<GLOBAL_POSITION_INT_DATA>, String> {
        self.evader
            .pump_until(&mut NoTarget, Duration::from_millis(1), &mut |_| false)?;
        let Some(fix) = self.evader.rover else {
            return Ok(None);
        };
        let t = f64::from(rover.time_ms.wrapping_sub(self.start_ms)) / 1000.0;
        if distance(rover.state, fix.state) <= self.eps || t > self.t_max {
            if t <= self.t_max {
                self.captured_ms = Some(rover.time_ms);
            }
            self.on = false;
            self.steer(0.0, 0.0, fix.speed)?;
            return Ok(None);
        }
        if self.last_fix_ms == Some(fix.time_ms) {
            return Ok(None);
        }
        self.last_fix_ms = Some(fix.time_ms);
        let (w, speed) = self.adversary.command(t, rover.state, fix.state);
        self.steer(w, speed, fix.speed)?;
        Ok(self.evader.position.clone())
    }
}

impl Injector for RoverTarget<'_> {
    fn before(&mut self, rover: &RoverFix) -> Option<GLOBAL_POSITION_INT_DATA> {
        if !self.on {
            return None;
        }
        self.step(rover).unwrap_or_else(|e| {
            eprintln!("xtask: the evader's rover: {e}");
            self.on = false;
            None
        })
    }

    fn on(&self) -> bool {
        self.on
    }

    fn captured_ms(&self) -> Option<u32> {
        self.captured_ms
    }
}

/// Flies `start` with the evader a rover of its own: launched at the start, at rest, driven by
/// `start.evader` within `limits`; the evader's peak and mean speed over the chase (m/s)
/// beside the outcome.
pub fn fly(
    h: &mut Harness,
    binary: &Path,
    start: Start,
    limits: [f64; 4],
    eps: f64,
    seed: u64,
    field: bool,
) -> Result<(Outcome, [f64; 2]), String> {
    let placed = place(h.rover.ok_or("no fix from the rover")?.state, &start);
    let wp_speed = limits[2];
    let mut evader = launch(binary, h, placed, wp_speed as f32)?;
    // Both at rest, where they stand now.
    let rover = h.rover.ok_or("no fix from the rover")?;
    let evader0 = evader
        .harness
        .rover
        .ok_or("no fix from the evader's rover")?
        .state;
    let params = chase_params(limits, rover.state, evader0, eps, h.chase_limit_s);
    let adversary = Adversary::new(Opponent::Evader(start.evader), limits, params.dt, eps, seed)
        .ok_or("the adversary's limits are invalid")?;
    let fixes_before = evader.harness.fixes.len();
    let target = RoverTarget {
        evader: &mut evader.harness,
        adversary,
        wp_speed,
        start_ms: rover.time_ms,
        eps,
        t_max: params.t_max,
        last_fix_ms: None,
        captured_ms: None,
        on: true,
    };
    let began = Began::new(start, rover, &params, seed);
    let outcome = pursue(h, target, &began, seed, field)?;
    let speeds: Vec<f64> = evader.harness.fixes[fixes_before..]
        .iter()
        .map(|f| f.speed)
        .collect();
    let peak = speeds.iter().copied().fold(0.0, f64::max);
    let mean = speeds.iter().sum::<f64>() / speeds.len().max(1) as f64;
    Ok((outcome, [peak, mean]))
}
