//! The evader a second ArduPlane SITL (`cargo xtask run --autopilot ardupilot|px4 --vehicle plane
//! --plane-evader`): instance 1, started with the pursuer [`EAST_M`] east of it, taken off to
//! [`HEIGHT`] (above the pursuer: capture is judged in the horizontal plane, so the two pass
//! over each other), slowed to its AIRSPEED_CRUISE and measured at its bank limit as the
//! pursuer is at its own. Before each chase the ground station flies both level apart, back to
//! back, to the start's distance; then the evader's strategy banks it through GUIDED roll
//! setpoints on its own link, and its GLOBAL_POSITION_INT is the unit's target (re-sent from
//! system 2, TC_TGT_SYSID).

use std::path::PathBuf;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use twocars_sim::autopilot::{Plane, HOME};
use twocars_sim::kinematics::{distance, wrap_pi};

use super::aircraft::{self, roll_setpoint};
use super::sitl::{Frame, Launch, Sitl};
use super::vehicle::{send_until, set_autopilot_param};
use crate::harness::autopilot::chase::Start;
use crate::harness::autopilot::evader::Steer;
use crate::harness::autopilot::harness::{Harness, NoTarget};
use crate::harness::autopilot::EVADERS;
use twocars_sim::sim::theorem_threshold;

/// How the evader's aircraft flies: its airspeed and the least it may fly at (m/s,
/// AIRSPEED_CRUISE and AIRSPEED_MIN), its bank limit (deg: small enough that it turns wider
/// than the pursuer's law allows the pursuer, w_em < w_pm, at its lower speed) and SITL's
/// speed-up.
#[derive(Clone, Copy, Debug)]
pub struct Spec {
    pub airspeed: f32,
    pub airspeed_min: f32,
    pub bank_deg: f64,
    pub speedup: u32,
}

/// Against ArduPlane (22 m/s airspeed, 45 degrees of bank): about 0.6 of its speed, plane.parm's
/// AIRSPEED_MIN.
pub const AGAINST_ARDUPLANE: Spec = Spec {
    airspeed: 14.0,
    airspeed_min: 10.0,
    bank_deg: 15.0,
    speedup: 4,
};
/// The evader's height above home, m: 30 m above the pursuer's.
const HEIGHT: f32 = 130.0;
/// The evader's home east of the pursuer's, m: the two take off side by side.
const EAST_M: f64 = 300.0;
/// The evader's SITL instance (TCP 5770): the pursuer is instance 0.
const INSTANCE: u16 = 1;
/// Bank per radian of heading error in the ground station's heading hold before a chase.
const HEADING_GAIN: f64 = 1.0;

/// The evader's aircraft: its SITL process, the ground station's link to it, how it was asked
/// to fly and how it flew when measured.
pub struct EvaderPlane {
    _sitl: Sitl,
    pub harness: Harness,
    pub spec: Spec,
    pub flown: aircraft::Flown,
}

/// Starts the evader's instance as `spec` says on a thread of its own: taken off, in GUIDED,
/// slowed to its airspeed, measured at its bank limit.
pub fn launch(binary: PathBuf, spec: Spec) -> JoinHandle<Result<EvaderPlane, String>> {
    std::thread::spawn(move || {
        let (lat, lon) = Plane::new(HOME).fix(0.0, EAST_M);
        let launch = Launch {
            frame: Frame::Plane,
            instance: INSTANCE,
            home: (f64::from(lat) * 1e-7, f64::from(lon) * 1e-7),
            heading: 0.0,
            speedup: spec.speedup,
        };
        let (sitl, serial0) = Sitl::start(&binary, launch)?;
        let router = crate::harness::autopilot::router::Router::alone(serial0)?;
        let mut harness = Harness::new(router, HOME, 0);
        aircraft::make_ready(&mut harness, HEIGHT)?;
        set_autopilot_param(&mut harness, "AIRSPEED_MIN", spec.airspeed_min)?;
        set_autopilot_param(&mut harness, "AIRSPEED_CRUISE", spec.airspeed)?;
        // Level while TECS slows the aircraft from its take-off speed to the new cruise.
        let settled = harness.now_ms() + 20_000;
        send_until(&mut harness, &roll_setpoint(0.0), settled)?;
        let flown = aircraft::measure(&mut harness, spec.bank_deg)?;
        Ok(EvaderPlane {
            _sitl: sitl,
            harness,
            spec,
            flown,
        })
    })
}

/// Waits for [`launch`]'s thread while `keep` flies the pursuer (reading its link, so that
/// no buffer fills; streaming what its mode needs).
pub fn join(
    starting: JoinHandle<Result<EvaderPlane, String>>,
    pursuer: &mut Harness,
    keep: &mut dyn FnMut(&mut Harness) -> Result<(), String>,
) -> Result<EvaderPlane, String> {
    while !starting.is_finished() {
        keep(pursuer)?;
    }
    starting
        .join()
        .map_err(|_| "the evader's start panicked".to_string())?
}

/// The bank (rad) that turns an aircraft on `heading` toward `wanted` (rad, clockwise), within
/// `limit_deg`.
fn heading_hold(heading: f64, wanted: f64, limit_deg: f64) -> f64 {
    let limit = limit_deg.to_radians();
    (HEADING_GAIN * wrap_pi(wanted - heading)).clamp(-limit, limit)
}

/// How far from the other's bearing (rad) each aircraft's heading may be when a chase starts.
const ALIGNED: f64 = 0.17;
/// The share of the start's distance two aircraft that began farther apart close to before
/// they turn away from each other.
const CLOSE_IN: f64 = 0.6;

/// The pursuer as the ground station banks it: its bank limit (deg), and how a bank (rad) is
/// sent to it.
pub struct Banked<'a> {
    pub limit_deg: f64,
    pub send: &'a mut dyn FnMut(&mut Harness, f64) -> Result<(), String>,
}

/// Flies the pursuer (behind `h`, banked by `pursuer`) and the evader level apart, each turned
/// away from the other, until they are `apart` (m) apart and each within [`ALIGNED`] of
/// heading straight away; where they start farther apart than that, each first turned toward
/// the other until they are within [`CLOSE_IN`] of `apart`. 240 s of wall clock at most.
pub fn fly_apart(
    h: &mut Harness,
    evader: &mut EvaderPlane,
    apart: f64,
    pursuer: Banked<'_>,
) -> Result<(), String> {
    let deadline = Instant::now() + Duration::from_secs(240);
    let mut closing = None;
    while Instant::now() < deadline {
        let fixes = h.fixes.len();
        h.pump_until(&mut NoTarget, Duration::from_millis(200), &mut |h| {
            h.fixes.len() > fixes
        })?;
        let e = &mut evader.harness;
        e.pump_until(&mut NoTarget, Duration::from_millis(1), &mut |_| false)?;
        let (Some(p), Some(q)) = (h.rover, e.rover) else {
            continue;
        };
        let d = distance(p.state, q.state);
        // Closing in where they start beyond `apart`, until within reach; then apart for good.
        let closing = closing.get_or_insert(d > apart);
        *closing &= d > CLOSE_IN * apart;
        let closing = *closing;
        let bearing = (q.state[1] - p.state[1]).atan2(q.state[0] - p.state[0]);
        let pi = std::f64::consts::PI;
        let (to_p, to_q) = match closing {
            true => (bearing, bearing + pi),
            false => (bearing + pi, bearing),
        };
        let turned = |heading: f64, wanted: f64| wrap_pi(wanted - heading).abs() < ALIGNED;
        if !closing && d >= apart && turned(p.state[2], to_p) && turned(q.state[2], to_q) {
            return Ok(());
        }
        (pursuer.send)(h, heading_hold(p.state[2], to_p, pursuer.limit_deg))?;
        let bank = heading_hold(q.state[2], to_q, evader.spec.bank_deg);
        e.router.send_to_autopilot(&roll_setpoint(bank))?;
    }
    Err(format!(
        "the two aircraft were not {apart:.0} m apart within 240 s"
    ))
}

/// The evader's aircraft told its strategy's turn as a GUIDED roll (ArduPlane's TECS holding
/// its airspeed and height): the bank of a turn at the measured efficiency.
pub struct PlaneSteer {
    /// Its ground speed level, m/s.
    pub speed: f64,
    /// The share of a coordinated turn it makes (as TC_BANK_EFF).
    pub efficiency: f64,
    /// Its bank limit, deg.
    pub limit_deg: f64,
}

impl PlaneSteer {
    /// The steering of `evader` as measured.
    pub fn of(evader: &EvaderPlane) -> PlaneSteer {
        PlaneSteer {
            speed: evader.flown.speed,
            efficiency: evader.flown.efficiency,
            limit_deg: evader.spec.bank_deg,
        }
    }
}

impl Steer for PlaneSteer {
    fn steer(&mut self, h: &mut Harness, w: f64, speed: f64, _: f64) -> Result<(), String> {
        let w = if speed > 0.0 { w } else { 0.0 };
        let bank = (self.speed * self.speed * w / (self.efficiency * 9.80665)).atan();
        let limit = self.limit_deg.to_radians();
        h.router
            .send_to_autopilot(&roll_setpoint(bank.clamp(-limit, limit)))
    }
}

/// The law's limits: the pursuer's `pursuer`, with the evader's aircraft's as [`limits`] sets
/// them where there is one (said in a line).
pub fn law_limits(pursuer: [f64; 4], evader: Option<&EvaderPlane>) -> Result<[f64; 4], String> {
    let Some(e) = evader else {
        return Ok(pursuer);
    };
    println!(
        "the evader, ArduPlane SITL instance 1 at AIRSPEED_CRUISE {} and {}x: {}",
        e.spec.airspeed,
        e.spec.speedup,
        e.flown.line(e.spec.bank_deg)
    );
    limits(pursuer, &e.flown)
}

/// The law's limits with the evader's as measured: v_em its level speed (to 0.1 m/s, up) and
/// w_em its curvature at its bank limit (three significant digits, up), so that it never flies
/// outside them; Err where it is not the slower and the wider-turning of the two.
pub fn limits(pursuer: [f64; 4], evader: &aircraft::Flown) -> Result<[f64; 4], String> {
    let up = |x: f64| {
        let scale = 10f64.powi(2 - x.log10().floor() as i32);
        (x * scale).ceil() / scale
    };
    let [v_pm, w_pm, ..] = pursuer;
    let (v_em, w_em) = ((evader.speed * 10.0).ceil() / 10.0, up(evader.curvature));
    if v_em < v_pm && w_em < w_pm {
        Ok([v_pm, w_pm, v_em, w_em])
    } else {
        Err(format!(
            "the evader's aircraft ({v_em} m/s, {w_em} 1/m) is not slower and wider-turning than \
             the pursuer's law ({v_pm} m/s, {w_pm} 1/m)"
        ))
    }
}

/// The starts against the evader's aircraft: the evader dead astern flying the other way, at
/// half the threshold and at 1.1 times it, against each of the suite's evaders (the first
/// alone with `short`).
pub fn starts(limits: [f64; 4], short: bool) -> Vec<Start> {
    let threshold = theorem_threshold(limits);
    let mut out = Vec::new();
    for (name, apart) in [("below", 0.5 * threshold), ("beyond", 1.1 * threshold)] {
        for evader in EVADERS {
            out.push(Start {
                name,
                ahead: -apart,
                right: 0.0,
                heading: std::f64::consts::PI,
                evader,
            });
        }
    }
    if short {
        out.truncate(1);
    }
    out
}
