//! The harness's view of the link: every frame forwarded, and what the chase needs read from it
//! (the pursuer's fixes and yaw rate, its mode and arming, the unit's setpoints and TC_T, both
//! sides' STATUSTEXTs), with the target's fix injected before each of the pursuer's. The
//! pursuer is called the rover here whichever vehicle it is.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use mavlink::dialects::common::{MavMessage, GLOBAL_POSITION_INT_DATA, HEARTBEAT_DATA};
use twocars_sim::autopilot::Plane;

use super::router::{RawFrame, Router, Source};

/// The autopilot's system and component (SYSID_THISMAV 1, the autopilot).
pub const AUTOPILOT: (u8, u8) = (1, 1);
/// The unit's component (MAV_COMP_ID_ONBOARD_COMPUTER).
pub const UNIT_COMPONENT: u8 = 191;
/// A velocity setpoint's course within this of the rover's heading (rad) is read as straight.
const STRAIGHT: f64 = 0.01;
/// HEARTBEAT base_mode's armed flag.
const ARMED: u8 = 128;
/// A team's unit's NAMED_VALUE_INT naming the chaser (`twocars::mavlink::team::CHASER`, which
/// xtask's build of the core lacks: without the `mavlink-team` feature, as the images it
/// checks are built).
const CHASER: &[u8] = b"TC_CHASER";

/// The rover as its GLOBAL_POSITION_INT reports it, in the plane about home.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoverFix {
    /// The autopilot's `time_boot_ms`.
    pub time_ms: u32,
    /// North, east (m) and heading (rad, clockwise from north).
    pub state: [f64; 3],
    /// Ground speed, m/s.
    pub speed: f64,
    /// Course over ground from the velocity (rad, clockwise from north): the heading less the
    /// wind's crab.
    pub course: f64,
    /// Height above home, m.
    pub height: f64,
}

/// Puts the target's fix on the unit's link before each of the rover's.
pub trait Injector {
    /// The target's GLOBAL_POSITION_INT for the rover's fix `rover`, if it has a new one.
    fn before(&mut self, rover: &RoverFix) -> Option<GLOBAL_POSITION_INT_DATA>;
    /// Whether the target is still on: not caught, not out of time.
    fn on(&self) -> bool;
    /// The rover's time at capture, ms.
    fn captured_ms(&self) -> Option<u32> {
        None
    }
}

/// No target.
pub struct NoTarget;

impl Injector for NoTarget {
    fn before(&mut self, _: &RoverFix) -> Option<GLOBAL_POSITION_INT_DATA> {
        None
    }
    fn on(&self) -> bool {
        false
    }
}

/// The unit's setpoint as the autopilot gets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setpoint {
    /// The rover's time at its arrival (its last fix), ms.
    pub time_ms: u32,
    /// Body yaw rate, rad/s (positive clockwise); for a velocity setpoint the turn it asks
    /// for: its course less the rover's heading (rad, clockwise), over TC_PERIOD.
    pub yaw_rate: f32,
    /// Thrust; for a velocity setpoint its speed, m/s.
    pub thrust: f32,
    /// For an attitude setpoint its roll, rad (positive right wing down); else 0.
    pub bank: f32,
}

/// What the harness has read so far.
pub struct Harness {
    pub router: Router,
    plane: Plane,
    /// The target's system id.
    pub target_system: u8,
    pub rover: Option<RoverFix>,
    /// The rover's last GLOBAL_POSITION_INT as it came.
    pub position: Option<GLOBAL_POSITION_INT_DATA>,
    /// The rover's yaw rate (ATTITUDE.yawspeed, rad/s) at the rover's time.
    pub yaw_rates: Vec<(u32, f32)>,
    /// The aircraft's roll (ATTITUDE.roll, rad) at its time.
    pub rolls: Vec<(u32, f32)>,
    /// The aircraft's airspeed (VFR_HUD, m/s) at its time.
    pub airspeeds: Vec<(u32, f32)>,
    /// The roll the autopilot's navigation demands (NAV_CONTROLLER_OUTPUT.nav_roll, deg).
    pub nav_rolls: Vec<(u32, f32)>,
    pub fixes: Vec<RoverFix>,
    pub armed: bool,
    pub mode: Option<u32>,
    /// The mode (HEARTBEAT's custom_mode) at each heartbeat, at the rover's time.
    pub modes: Vec<(u32, u32)>,
    /// STATUSTEXTs with the rover's time and their source.
    pub texts: Vec<(u32, Source, String)>,
    pub setpoints: Vec<Setpoint>,
    /// The unit's TC_T at the rover's time.
    pub tc_t: Vec<(u32, f32)>,
    /// The unit's TC_CHASER (the system id its team names the chaser; 0: none) at the rover's
    /// time, where it is in a team.
    pub chasers: Vec<(u32, i32)>,
    /// The unit's last TC_BADFRM.
    pub bad_frames: Option<f32>,
    /// The unit's last signature refusals by kind (TC_NOSIG, TC_BADSIG, TC_OLDSIG), where it
    /// signs.
    pub refusals: [Option<f32>; 3],
    /// Frames from the autopilot that were signed, and that were not.
    pub autopilot_signed: (u64, u64),
    /// PARAM_VALUEs (source, name, value).
    pub params: Vec<(Source, String, f32)>,
    /// COMMAND_ACKs from the autopilot (command, result).
    pub acks: Vec<(u32, u8)>,
    /// Frames from the autopilot by message id, and their bytes.
    pub autopilot_frames: BTreeMap<u32, (u64, u64)>,
    last_gcs_heartbeat: Option<Instant>,
    /// What the autopilot says when it stops for want of setpoints (a STATUSTEXT's part).
    pub stop_text: &'static str,
    /// The unit's TC_PERIOD, s: a velocity setpoint's turn is over it.
    pub period: f32,
    /// The unit's TC_V_PM (m/s) and TC_BANK_EFF: an attitude setpoint's roll is read as the
    /// turn rate TC_BANK_EFF g tan(roll) / TC_V_PM.
    pub bank_turn: (f32, f32),
    /// The pursuer: a rover stops when the setpoints end, an aircraft flies on.
    pub pursuer: Pursuer,
    /// A chase's time limit, s of the autopilot's clock.
    pub chase_limit_s: f64,
}

/// What kind of vehicle the pursuer is: what the failsafe after a chase is timed to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pursuer {
    /// Timed to its standstill.
    Rover,
    /// Timed to its navigation's own roll (the autopilot's setpoint timeout).
    Aircraft,
}

impl Harness {
    pub fn new(router: Router, home: (i32, i32), target_system: u8) -> Self {
        Harness {
            router,
            plane: Plane::new(home),
            target_system,
            rover: None,
            position: None,
            yaw_rates: Vec::new(),
            rolls: Vec::new(),
            airspeeds: Vec::new(),
            nav_rolls: Vec::new(),
            fixes: Vec::new(),
            armed: false,
            mode: None,
            modes: Vec::new(),
            texts: Vec::new(),
            setpoints: Vec::new(),
            tc_t: Vec::new(),
            chasers: Vec::new(),
            bad_frames: None,
            refusals: [None; 3],
            autopilot_signed: (0, 0),
            params: Vec::new(),
            acks: Vec::new(),
            autopilot_frames: BTreeMap::new(),
            last_gcs_heartbeat: None,
            stop_text: "target not received",
            period: 1.0,
            bank_turn: (1.0, 1.0),
            pursuer: Pursuer::Rover,
            chase_limit_s: 120.0,
        }
    }

    /// The plane about home.
    pub fn plane(&self) -> &Plane {
        &self.plane
    }

    /// The rover's time now (its last fix), ms.
    pub fn now_ms(&self) -> u32 {
        self.rover.map_or(0, |r| r.time_ms)
    }

    /// Forwards frames for `duration` (wall clock) or until `done` holds; whether it held.
    pub fn pump_until(
        &mut self,
        injector: &mut dyn Injector,
        duration: Duration,
        done: &mut dyn FnMut(&Harness) -> bool,
    ) -> Result<bool, String> {
        let deadline = Instant::now() + duration;
        loop {
            if done(self) {
                return Ok(true);
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Ok(false);
            }
            self.gcs_heartbeat()?;
            if let Some((source, frame)) = self.router.next(left.min(Duration::from_millis(50)))? {
                self.handle(source, &frame, injector)?;
            }
        }
    }

    /// A ground station's heartbeat to the autopilot, once a second.
    fn gcs_heartbeat(&mut self) -> Result<(), String> {
        if self
            .last_gcs_heartbeat
            .is_some_and(|t| t.elapsed() < Duration::from_secs(1))
        {
            return Ok(());
        }
        self.last_gcs_heartbeat = Some(Instant::now());
        let heartbeat = HEARTBEAT_DATA {
            mavtype: mavlink::dialects::common::MavType::MAV_TYPE_GCS,
            autopilot: mavlink::dialects::common::MavAutopilot::MAV_AUTOPILOT_INVALID,
            ..Default::default()
        };
        self.router.send_to_autopilot(&heartbeat)
    }

    fn handle(
        &mut self,
        source: Source,
        frame: &RawFrame,
        injector: &mut dyn Injector,
    ) -> Result<(), String> {
        let message = frame.message();
        if source == Source::Autopilot {
            let entry = self.autopilot_frames.entry(frame.message_id).or_default();
            entry.0 += 1;
            entry.1 += frame.bytes.len() as u64;
            match frame.bytes.get(..3) {
                Some([0xFD, _, flags]) if flags & 1 != 0 => self.autopilot_signed.0 += 1,
                _ => self.autopilot_signed.1 += 1,
            }
            if (frame.system, frame.component) == AUTOPILOT {
                if let Some(MavMessage::GLOBAL_POSITION_INT(p)) = &message {
                    let fix = self.rover_fix(p);
                    self.rover = Some(fix);
                    self.position = Some(p.clone());
                    self.fixes.push(fix);
                    if let Some(target) = injector.before(&fix) {
                        let sender = (self.target_system, 1);
                        self.router.send_to_unit_as(sender, &target)?;
                    }
                }
            }
        }
        self.router.forward(source, frame)?;
        if let Some(message) = message {
            self.observe(source, frame, message);
        }
        Ok(())
    }

    fn rover_fix(&self, p: &GLOBAL_POSITION_INT_DATA) -> RoverFix {
        let (north, east) = self.plane.local((p.lat, p.lon));
        let (vn, ve) = (f64::from(p.vx) / 100.0, f64::from(p.vy) / 100.0);
        let heading = if p.hdg == u16::MAX {
            ve.atan2(vn)
        } else {
            (f64::from(p.hdg) / 100.0).to_radians()
        };
        RoverFix {
            time_ms: p.time_boot_ms,
            state: [north, east, heading],
            speed: vn.hypot(ve),
            course: ve.atan2(vn),
            height: f64::from(p.relative_alt) / 1000.0,
        }
    }

    fn observe(&mut self, source: Source, frame: &RawFrame, message: MavMessage) {
        let now = self.now_ms();
        let from_unit = source == Source::Unit && frame.component == UNIT_COMPONENT;
        let from_autopilot = (frame.system, frame.component) == AUTOPILOT;
        match message {
            MavMessage::HEARTBEAT(h) if from_autopilot => {
                self.armed = h.base_mode.bits() & ARMED != 0;
                self.mode = Some(h.custom_mode);
                self.modes.push((now, h.custom_mode));
            }
            MavMessage::ATTITUDE(a) if from_autopilot => {
                self.yaw_rates.push((now, a.yawspeed));
                self.rolls.push((now, a.roll));
            }
            MavMessage::VFR_HUD(v) if from_autopilot => self.airspeeds.push((now, v.airspeed)),
            MavMessage::NAV_CONTROLLER_OUTPUT(n) if from_autopilot => {
                self.nav_rolls.push((now, n.nav_roll));
            }
            MavMessage::COMMAND_ACK(a) if from_autopilot => {
                self.acks.push((a.command as u32, a.result as u8));
            }
            MavMessage::STATUSTEXT(t) => {
                let text = String::from_utf8_lossy(&t.text[..])
                    .trim_end_matches('\0')
                    .to_string();
                self.texts.push((now, source, text));
            }
            MavMessage::PARAM_VALUE(p) => {
                let name = String::from_utf8_lossy(&p.param_id[..])
                    .trim_end_matches('\0')
                    .to_string();
                self.params.push((source, name, p.param_value));
            }
            MavMessage::SET_ATTITUDE_TARGET(s) if from_unit => {
                let setpoint = self.attitude_setpoint(&s, now);
                self.setpoints.push(setpoint);
            }
            MavMessage::SET_POSITION_TARGET_LOCAL_NED(s) if from_unit => {
                let heading = self.rover.map_or(0.0, |r| r.state[2]);
                let course = f64::from(s.vy).atan2(f64::from(s.vx));
                let turn = twocars_sim::kinematics::wrap_pi(course - heading);
                // The unit runs straight on its own estimate of the heading the fix gave: a
                // course within STRAIGHT of it is no turn.
                let turn = if turn.abs() < STRAIGHT { 0.0 } else { turn };
                self.setpoints.push(Setpoint {
                    time_ms: now,
                    yaw_rate: turn as f32 / self.period,
                    thrust: s.vx.hypot(s.vy),
                    bank: 0.0,
                });
            }
            MavMessage::NAMED_VALUE_INT(n) if from_unit && n.name.starts_with(CHASER) => {
                self.chasers.push((now, n.value));
            }
            MavMessage::NAMED_VALUE_FLOAT(n) if from_unit => {
                let name = String::from_utf8_lossy(&n.name[..])
                    .trim_end_matches('\0')
                    .to_string();
                let refusal = twocars::mavlink::SIGNATURE_COUNTERS
                    .iter()
                    .position(|&c| c == name);
                match (name.as_str(), refusal) {
                    ("TC_T", _) => self.tc_t.push((now, n.value)),
                    ("TC_BADFRM", _) => self.bad_frames = Some(n.value),
                    (_, Some(i)) => self.refusals[i] = Some(n.value),
                    _ => {}
                }
            }
            _ => {}
        }
    }

    /// The unit's SET_ATTITUDE_TARGET: its yaw rate, or where the attitude is used (type_mask
    /// bit 128 clear, or the roll rate's bit 1 clear) the turn rate its roll asks for.
    fn attitude_setpoint(
        &self,
        s: &mavlink::dialects::common::SET_ATTITUDE_TARGET_DATA,
        now: u32,
    ) -> Setpoint {
        let mask = s.type_mask.bits();
        if mask & 128 != 0 && mask & 1 != 0 {
            return Setpoint {
                time_ms: now,
                yaw_rate: s.body_yaw_rate,
                thrust: s.thrust,
                bank: 0.0,
            };
        }
        let [w, x, y, z] = s.q;
        let bank = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
        let (speed, efficiency) = self.bank_turn;
        Setpoint {
            time_ms: now,
            yaw_rate: efficiency * twocars::geodetic::STANDARD_GRAVITY * bank.tan() / speed,
            thrust: s.thrust,
            bank,
        }
    }

    /// Whether a STATUSTEXT from `source` containing `needle` came at or after index `from`.
    pub fn text_since(&self, from: usize, source: Source, needle: &str) -> Option<u32> {
        self.texts
            .iter()
            .skip(from)
            .find(|(_, s, t)| *s == source && t.contains(needle))
            .map(|(time, _, _)| *time)
    }
}

/// Forwards until the rover's ground speed is under 0.1 m/s (`seconds` of wall clock at
/// most); its time then.
pub fn wait_stopped(
    h: &mut Harness,
    injector: &mut dyn Injector,
    seconds: f64,
) -> Result<u32, String> {
    let stopped = |h: &Harness| h.rover.is_some_and(|r| r.speed < 0.1);
    if h.pump_until(injector, Duration::from_secs_f64(seconds), &mut |h| {
        stopped(h)
    })? {
        Ok(h.now_ms())
    } else {
        Err(format!("the rover did not stop within {seconds} s"))
    }
}
