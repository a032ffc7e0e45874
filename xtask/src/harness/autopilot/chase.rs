//! One chase: the simulated target (an evader of the adversary suite, a Dubins car at the
//! law's evader limits) placed relative to the rover, its fix on the unit's link before each of
//! the rover's; the unit flies the rover; capture when the rover's fix is within the capture
//! radius; then the target goes silent and the failsafe chain is timed: the unit's last
//! setpoint, the autopilot's word that it stopped (ArduPilot's "target not received") and the
//! rover at a standstill, or an aircraft's navigation back at its own roll.

use std::time::Duration;

use mavlink::dialects::common::GLOBAL_POSITION_INT_DATA;
use twocars::{Policy, Variant};
use twocars_sim::adversary::{Adversary, EvaderKind, Opponent};
use twocars_sim::autopilot::{hdg_cdeg, velocity_cm_s};
use twocars_sim::kinematics::{advance, distance};
use twocars_sim::sim::{simulate_with, Setup, SimParams, SimStatus};

use super::field::{Delayed, Radio};
use super::harness::wait_stopped;
use super::harness::{Harness, Injector, Pursuer, RoverFix};
use super::router::Source;

/// A start: the evader's position and heading in the rover's frame at the start (metres ahead,
/// metres to the right, heading relative to the rover's, rad), and its strategy.
#[derive(Clone, Copy, Debug)]
pub struct Start {
    pub name: &'static str,
    pub ahead: f64,
    pub right: f64,
    pub heading: f64,
    pub evader: EvaderKind,
}

/// The evader as the host simulates it.
pub struct Target {
    adversary: Adversary,
    state: [f64; 3],
    command: (f64, f64),
    last_ms: u32,
    start_ms: u32,
    eps: f64,
    t_max: f64,
    /// The rover's time at capture, ms.
    captured_ms: Option<u32>,
    /// Whether the target is still on (not captured, not timed out).
    on: bool,
    plane: twocars_sim::autopilot::Plane,
}

impl Injector for Target {
    fn before(&mut self, rover: &RoverFix) -> Option<GLOBAL_POSITION_INT_DATA> {
        if !self.on {
            return None;
        }
        let dt = f64::from(rover.time_ms.wrapping_sub(self.last_ms)) / 1000.0;
        let (w, speed) = self.command;
        self.state = advance(self.state, speed, w, dt);
        self.last_ms = rover.time_ms;
        let t = f64::from(rover.time_ms.wrapping_sub(self.start_ms)) / 1000.0;
        if distance(rover.state, self.state) <= self.eps {
            self.captured_ms = Some(rover.time_ms);
            self.on = false;
            return None;
        }
        if t > self.t_max {
            self.on = false;
            return None;
        }
        self.command = self.adversary.command(t, rover.state, self.state);
        let (lat, lon) = self.plane.fix(self.state[0], self.state[1]);
        let (vx, vy) = velocity_cm_s(self.command.1, self.state[2]);
        Some(GLOBAL_POSITION_INT_DATA {
            time_boot_ms: rover.time_ms,
            lat,
            lon,
            alt: 584_000,
            relative_alt: 0,
            vx,
            vy,
            vz: 0,
            hdg: hdg_cdeg(self.state[2]),
        })
    }

    fn on(&self) -> bool {
        self.on
    }

    fn captured_ms(&self) -> Option<u32> {
        self.captured_ms
    }
}

/// What one chase showed.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub start: Start,
    /// The distance at the start, m.
    pub distance: f64,
    /// The law's upper value at the start (the host's f32 law, the full speed assumed), s.
    pub predicted: f64,
    /// The unit's first TC_T, s.
    pub unit_predicted: Option<f32>,
    /// The host's closed loop from the same start against the same evader, the pursuer a Dubins
    /// car at full speed from t = 0, s (infinite if it never captured).
    pub ideal: f64,
    /// Capture time on the rover's clock, s (None: never captured).
    pub captured: Option<f64>,
    /// The distance the rover fell short of v_pm t by capture, m.
    pub speed_deficit: f64,
    /// The rover's speed at 1 s, m/s.
    pub speed_at_1s: f64,
    /// RMS of (rover yaw rate - setpoint yaw rate) over the chase, rad/s; and the same over the
    /// periods more than 0.5 s after a setpoint changed sign.
    pub tracking_rms: f64,
    /// The RMS away from the switches.
    pub tracking_rms_settled: f64,
    /// Setpoints sent during the chase.
    pub setpoints: usize,
    /// The chase's setpoints whose yaw rate has the sign opposite to the last nonzero one's.
    pub flips: usize,
    /// From the unit's last setpoint to the autopilot's word that it stopped
    /// ([`Harness::stop_text`]), s.
    pub to_stop_message: Option<f64>,
    /// From the unit's last setpoint to the autopilot's own failsafe: a rover at a standstill,
    /// an aircraft's navigation demanding a roll of its own, s.
    pub to_failsafe: Option<f64>,
    /// The least and the greatest airspeed through the chase (VFR_HUD), m/s.
    pub airspeed: Option<(f64, f64)>,
    /// The least and the greatest height above home through the chase, m.
    pub height: (f64, f64),
    /// The unit's "target stale" STATUSTEXT after capture, s after capture.
    pub unit_stale_after: Option<f64>,
    /// The rover's time at the chase's end (capture or time-out), ms.
    pub end_ms: u32,
    /// How far behind its link the unit fell at most, s of the autopilot's clock: the most it
    /// held unread over the chase's byte rate to it (None where unmeasured).
    pub unit_lag: Option<f64>,
}

/// Where the evader starts: `start`'s offsets in the frame of the rover at `rover`.
pub fn place(rover: [f64; 3], start: &Start) -> [f64; 3] {
    let [rx, ry, rt] = rover;
    let (s, c) = rt.sin_cos();
    [
        rx + start.ahead * c - start.right * s,
        ry + start.ahead * s + start.right * c,
        rt + start.heading,
    ]
}

/// The host's closed loop of `params` against `evader`: the pursuer a Dubins car at full speed
/// from t = 0 with the unit's law (f32, flight policy, told the capture radius).
fn ideal_run(params: &SimParams, evader: EvaderKind, seed: u64) -> twocars_sim::sim::SimResult {
    let setup = Setup {
        capture_radius: true,
        opponent: Some((Opponent::Evader(evader), seed)),
        ..Setup::default()
    };
    simulate_with::<f32>(params, Variant::Paper, Policy::Flight, false, setup)
}

/// Where the harness's records stood when a chase began.
struct Marks {
    setpoints: usize,
    tc_t: usize,
    texts: usize,
    fixes: usize,
    rates: usize,
    to_unit: usize,
}

impl Marks {
    fn now(h: &Harness) -> Marks {
        Marks {
            to_unit: h.router.to_unit_log.len(),
            setpoints: h.setpoints.len(),
            tc_t: h.tc_t.len(),
            texts: h.texts.len(),
            fixes: h.fixes.len(),
            rates: h.yaw_rates.len(),
        }
    }
}

/// Flies `start` from where the rover stands; `limits` are the law's (v_pm, w_pm, v_em, w_em);
/// with a `field` the target's fixes come through it ([`Delayed`]).
pub fn fly(
    h: &mut Harness,
    start: Start,
    limits: [f64; 4],
    eps: f64,
    seed: u64,
    field: Option<Radio>,
) -> Result<Outcome, String> {
    let rover = h.rover.ok_or("no fix from the rover")?;
    let evader0 = place(rover.state, &start);
    let params = chase_params(limits, rover.state, evader0, eps, h.chase_limit_s);
    let adversary = Adversary::new(Opponent::Evader(start.evader), limits, params.dt, eps, seed)
        .ok_or("the adversary's limits are invalid")?;
    let target = Target {
        adversary,
        state: evader0,
        command: (0.0, limits[2]),
        last_ms: rover.time_ms,
        start_ms: rover.time_ms,
        eps,
        t_max: params.t_max,
        captured_ms: None,
        on: true,
        plane: *h.plane(),
    };
    let began = Began::new(start, rover, &params, seed);
    pursue(h, target, &began, seed, field)
}

/// A chase's parameters from the rover's and the evader's states: the host's step is the
/// rover's fix interval.
pub fn chase_params(
    limits: [f64; 4],
    pursuer: [f64; 3],
    evader: [f64; 3],
    eps: f64,
    t_max: f64,
) -> SimParams {
    SimParams {
        limits,
        pursuer,
        evader,
        dt: f64::from(super::message::STREAM_INTERVAL_US) * 1e-6,
        t_max,
        eps,
    }
}

/// How a chase began: the start, both states, the ideal pursuer's run from them.
pub struct Began {
    pub start: Start,
    pub rover: RoverFix,
    pub evader0: [f64; 3],
    pub ideal: twocars_sim::sim::SimResult,
    pub v_pm: f64,
}

impl Began {
    /// A chase from `params`' states, the rover's fix `rover`, against `start.evader`.
    pub fn new(start: Start, rover: RoverFix, params: &SimParams, seed: u64) -> Began {
        Began {
            start,
            rover,
            evader0: params.evader,
            ideal: ideal_run(params, start.evader, seed),
            v_pm: params.limits[0],
        }
    }
}

/// Forwards until `target` is caught or out of time (its fixes through [`Delayed`] with a
/// `field`), then times the failsafe; the outcome.
pub fn pursue<T: Injector>(
    h: &mut Harness,
    target: T,
    began: &Began,
    seed: u64,
    field: Option<Radio>,
) -> Result<Outcome, String> {
    let marks = Marks::now(h);
    h.router.take_unread();
    let mode = h.mode;
    let wall = std::time::Instant::now() + Duration::from_secs_f64(h.chase_limit_s * 2.0 + 10.0);
    // Through the field, the target's fixes come late, sparse and noisy.
    let mut delayed = Delayed::new(target, field.unwrap_or(Radio::ROVER), seed);
    while delayed.on() {
        if std::time::Instant::now() > wall {
            return Err("the chase outran its wall-clock limit".to_string());
        }
        let injector: &mut dyn Injector = if field.is_some() {
            &mut delayed
        } else {
            delayed.inner_mut()
        };
        h.pump_until(injector, Duration::from_millis(100), &mut |_| false)?;
    }
    let end_ms = h.now_ms();
    let unit_lag = unit_lag(h, &marks, end_ms.wrapping_sub(began.rover.time_ms));
    // The failsafe: the target is silent from here; a rover must come to a standstill, an
    // aircraft's autopilot take its roll back.
    let failsafe_ms = match h.pursuer {
        Pursuer::Rover => wait_stopped(h, &mut delayed, 15.0).ok(),
        Pursuer::Aircraft => wait_own_roll(h, &mut delayed, (marks.setpoints, mode), 15.0)?,
    };
    let ended = Ended {
        start: began.start,
        rover: began.rover,
        evader0: began.evader0,
        ideal: began.ideal.clone(),
        captured_ms: delayed.captured_ms(),
        end_ms,
        failsafe_ms,
        v_pm: began.v_pm,
        unit_lag,
    };
    Ok(outcome(h, &marks, &ended))
}

/// The most the unit held unread since `marks` over the bytes sent it per second of the
/// autopilot's clock through the `chase_ms` since: how late, at worst, it read its states (s).
fn unit_lag(h: &mut Harness, marks: &Marks, chase_ms: u32) -> Option<f64> {
    let unread = h.router.take_unread()?;
    let sent: usize = h.router.to_unit_log[marks.to_unit..]
        .iter()
        .map(|(_, b)| b.len())
        .sum();
    let per_s = sent as f64 / (f64::from(chase_ms.max(1)) / 1000.0);
    Some(unread as f64 / per_s.max(1.0))
}

/// A nav roll this far from the unit's last bank (deg) is the autopilot's own.
const OWN_ROLL_DEG: f32 = 2.0;

/// Forwards until the autopilot flies on its own after the unit's last setpoint (the
/// setpoints since `chase.0`): its navigation demands a roll more than [`OWN_ROLL_DEG`] from
/// the unit's last bank (ArduPlane), or it leaves the chase's mode `chase.1` (PX4's offboard
/// loss); `seconds` of wall clock at most; its time then.
fn wait_own_roll(
    h: &mut Harness,
    injector: &mut dyn Injector,
    chase: (usize, Option<u32>),
    seconds: f64,
) -> Result<Option<u32>, String> {
    let own = |h: &Harness| {
        let last = h.setpoints[chase.0..].last()?;
        let bank = last.bank.to_degrees();
        let after = |t: &u32| *t > last.time_ms;
        let rolled = h
            .nav_rolls
            .iter()
            .filter(|(t, roll)| after(t) && (roll - bank).abs() > OWN_ROLL_DEG)
            .map(|(t, _)| *t)
            .next();
        let left = h
            .modes
            .iter()
            .filter(|(t, mode)| after(t) && Some(*mode) != chase.1)
            .map(|(t, _)| *t)
            .next();
        rolled.into_iter().chain(left).min()
    };
    // The unit's setpoints must have ended first: no setpoint for a second of wall clock.
    let mut count = h.setpoints.len();
    let mut quiet_since = std::time::Instant::now();
    let deadline = std::time::Instant::now() + Duration::from_secs_f64(seconds);
    while std::time::Instant::now() < deadline {
        h.pump_until(injector, Duration::from_millis(100), &mut |_| false)?;
        if h.setpoints.len() != count {
            count = h.setpoints.len();
            quiet_since = std::time::Instant::now();
        } else if quiet_since.elapsed() > Duration::from_secs(1) {
            if let Some(t) = own(h) {
                return Ok(Some(t));
            }
        }
    }
    Ok(None)
}

/// A chase as it ended.
struct Ended {
    start: Start,
    /// The rover's fix and the evader's state at the start.
    rover: RoverFix,
    evader0: [f64; 3],
    ideal: twocars_sim::sim::SimResult,
    /// The rover's time at capture, at the chase's end (capture or time-out) and at the
    /// autopilot's own failsafe after it, ms.
    captured_ms: Option<u32>,
    end_ms: u32,
    failsafe_ms: Option<u32>,
    v_pm: f64,
    unit_lag: Option<f64>,
}

/// The chase `e` as the harness recorded it since `marks`.
fn outcome(h: &Harness, marks: &Marks, e: &Ended) -> Outcome {
    let Ended {
        rover,
        end_ms,
        failsafe_ms,
        ..
    } = *e;
    let last_setpoint = h.setpoints[marks.setpoints..].last().map(|s| s.time_ms);
    let seconds = |from: u32, to: u32| f64::from(to.wrapping_sub(from)) / 1000.0;
    let stop_message = h.text_since(marks.texts, Source::Autopilot, h.stop_text);
    let unit_stale = h.text_since(marks.texts, Source::Unit, "target stale");
    let chase_fixes: Vec<RoverFix> = h.fixes[marks.fixes..]
        .iter()
        .copied()
        .filter(|f| f.time_ms <= end_ms)
        .collect();
    let (tracking_rms, tracking_rms_settled) = tracking(
        &h.setpoints[marks.setpoints..],
        &h.yaw_rates[marks.rates..],
        end_ms,
    );
    Outcome {
        start: e.start,
        distance: distance(rover.state, e.evader0),
        predicted: e.ideal.predicted,
        unit_predicted: h.tc_t.get(marks.tc_t).map(|(_, v)| *v),
        ideal: if e.ideal.status == SimStatus::Captured {
            e.ideal.t_capture
        } else {
            f64::INFINITY
        },
        captured: e.captured_ms.map(|t| seconds(rover.time_ms, t)),
        speed_deficit: speed_deficit(&chase_fixes, rover.time_ms, e.v_pm),
        speed_at_1s: chase_fixes
            .iter()
            .find(|f| f.time_ms >= rover.time_ms + 1000)
            .map_or(f64::NAN, |f| f.speed),
        tracking_rms,
        tracking_rms_settled,
        setpoints: h.setpoints.len() - marks.setpoints,
        flips: flips(&h.setpoints[marks.setpoints..], end_ms),
        to_stop_message: last_setpoint.zip(stop_message).map(|(a, b)| seconds(a, b)),
        to_failsafe: last_setpoint.zip(failsafe_ms).map(|(a, b)| seconds(a, b)),
        airspeed: range(
            h.airspeeds
                .iter()
                .filter(|(t, _)| (rover.time_ms..=end_ms).contains(t))
                .map(|(_, v)| f64::from(*v)),
        ),
        height: range(chase_fixes.iter().map(|f| f.height)).unwrap_or((f64::NAN, f64::NAN)),
        unit_stale_after: unit_stale.map(|t| seconds(end_ms, t)),
        end_ms,
        unit_lag: e.unit_lag,
    }
}

/// The least and the greatest of `values`; `None` where there are none.
fn range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |r, v| match r {
        None => Some((v, v)),
        Some((lo, hi)) => Some((f64::min(lo, v), f64::max(hi, v))),
    })
}

/// The setpoints up to `end_ms` whose yaw rate's sign is opposite to the last nonzero one's.
fn flips(setpoints: &[super::harness::Setpoint], end_ms: u32) -> usize {
    let mut last = 0.0f32;
    let mut count = 0;
    for s in setpoints
        .iter()
        .filter(|s| s.time_ms <= end_ms && s.yaw_rate != 0.0)
    {
        count += usize::from(last != 0.0 && s.yaw_rate.signum() != last.signum());
        last = s.yaw_rate;
    }
    count
}

/// The distance the rover fell short of `v_pm` t over `fixes` (trapezoids), m.
fn speed_deficit(fixes: &[RoverFix], start_ms: u32, v_pm: f64) -> f64 {
    let mut deficit = 0.0;
    let mut last = (start_ms, fixes.first().map_or(0.0, |f| f.speed));
    for f in fixes {
        let dt = f64::from(f.time_ms.wrapping_sub(last.0)) / 1000.0;
        deficit += dt * (v_pm - 0.5 * (f.speed + last.1));
        last = (f.time_ms, f.speed);
    }
    deficit
}

/// RMS of the rover's yaw rate less the setpoint in force, over every ATTITUDE up to
/// `end_ms`; and over those more than 0.5 s after the setpoint last changed sign.
fn tracking(
    setpoints: &[super::harness::Setpoint],
    rates: &[(u32, f32)],
    end_ms: u32,
) -> (f64, f64) {
    let (mut all, mut settled) = (Vec::new(), Vec::new());
    let mut k = 0;
    let mut flipped_ms = None;
    for &(t, rate) in rates.iter().filter(|(t, _)| *t <= end_ms) {
        while k + 1 < setpoints.len() && setpoints[k + 1].time_ms <= t {
            if setpoints[k + 1].yaw_rate.signum() != setpoints[k].yaw_rate.signum() {
                flipped_ms = Some(setpoints[k + 1].time_ms);
            }
            k += 1;
        }
        let Some(sp) = setpoints.get(k).filter(|s| s.time_ms <= t) else {
            continue;
        };
        let e = f64::from(rate - sp.yaw_rate);
        all.push(e * e);
        if flipped_ms.is_none_or(|f: u32| t.wrapping_sub(f) > 500) {
            settled.push(e * e);
        }
    }
    let rms = |v: &[f64]| (v.iter().sum::<f64>() / v.len().max(1) as f64).sqrt();
    (rms(&all), rms(&settled))
}
