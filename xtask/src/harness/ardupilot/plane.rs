//! `cargo xtask run --link ardupilot --vehicle plane`: ArduPlane SITL flies the pursuer in
//! GUIDED, the unit's roll-only attitude setpoints (TC_VEHICLE 3) turning it while ArduPlane's
//! TECS holds airspeed and height; the target an evader of the adversary suite simulated as a
//! Dubins car at the law's evader limits (docs/ardupilot.md).

use std::path::PathBuf;

use twocars_sim::autopilot::HOME;

use super::aircraft::{self, MEASURED_BANK_DEG};
use super::plane_evader::{self, Banked, PlaneSteer};
use super::rover_evader::pump;
use super::sitl::{self, Frame};
use super::vehicle::set_autopilot_param;
use crate::harness::autopilot::chase::{self, Outcome};
use crate::harness::autopilot::evader::{self, Terms};
use crate::harness::autopilot::field::Radio;
use crate::harness::autopilot::harness::{Harness, Pursuer};
use crate::harness::autopilot::{
    aircraft_limits, configure_unit, energy_line, report, set_unit_params, starts, TARGET_SYSTEM,
};
use twocars_sim::sim::theorem_threshold;

/// Capture radius, m: the SITL plane's span (about 2 m) less nothing, plus three sigma of a
/// GPS fix (1 m): two aircraft whose fixes are this close touch or nearly so.
pub const CAPTURE_RADIUS: f64 = 5.0;
/// A chase's time limit, s of the plane's clock: the starts beyond the threshold take minutes.
const CHASE_LIMIT_S: f64 = 600.0;
/// How much faster than the wall clock SITL runs by default: the unit's estimator and period
/// run on the autopilot's clock (`time_boot_ms`), and the chases at 4x capture as at 1x
/// (docs/ardupilot.md).
pub const SPEEDUP: u32 = 4;

/// The wind both aircraft fly in with `--field`: SIM_WIND_SPD and SIM_WIND_TURB, m/s.
pub const WIND: (f32, f32) = (6.0, 2.0);

/// `cargo xtask run --link ardupilot --vehicle plane`'s options.
#[derive(Debug, Clone)]
pub struct Options {
    /// The `arduplane` SITL binary (default: `TWOCARS_ARDUPLANE`, then
    /// `../shared/ardupilot/arduplane`).
    pub arduplane: Option<PathBuf>,
    /// One short chase instead of the whole set (what `cargo xtask test` flies).
    pub short: bool,
    /// The unit the `twocars-companion` binary on the host, not the QEMU image.
    pub companion: bool,
    /// SITL's speed-up over the wall clock.
    pub speedup: u32,
    /// The evader a second ArduPlane SITL flown by the suite's evaders, in place of the
    /// simulated one.
    pub plane_evader: bool,
    /// The target's fixes through [`Radio::AIRCRAFT`], the unit told so; against the evader's
    /// aircraft, both in the same wind ([`WIND`]).
    pub field: bool,
    /// The unit's link signed both ways with this key.
    pub key: Option<crate::image::signing::SigningKey>,
}

/// What `fly` flew.
pub struct Flown {
    pub outcomes: Vec<Outcome>,
    pub aircraft: aircraft::Flown,
    pub limits: [f64; 4],
    /// TC_BANK_EFF as set.
    pub efficiency: f64,
    /// Against the evader's aircraft: its mean ground speed over each chase, m/s.
    pub evader_speeds: Vec<f64>,
}

/// Runs the chases.
pub fn fly(options: &Options) -> Result<Flown, String> {
    let binary = sitl::find(Frame::Plane, options.arduplane.as_deref()).ok_or(
        "ArduPlane SITL not found: give --arduplane PATH or set TWOCARS_ARDUPLANE \
         (docs/ardupilot.md says how to build it)",
    )?;
    let (launched, _sitl, router) = super::link::connect(
        &binary,
        Frame::Plane,
        options.speedup,
        options.companion,
        options.key.as_ref(),
    )?;
    let evader_start = options.plane_evader.then(|| {
        plane_evader::launch(
            binary.clone(),
            plane_evader::Spec {
                speedup: options.speedup,
                ..plane_evader::AGAINST_ARDUPLANE
            },
        )
    });
    let mut h = Harness::new(router, HOME, TARGET_SYSTEM);
    h.pursuer = Pursuer::Aircraft;
    h.chase_limit_s = CHASE_LIMIT_S;
    println!(
        "ArduPlane SITL at {}x the wall clock: {}",
        options.speedup,
        binary.display()
    );
    let ready_s = aircraft::make_ready(&mut h, aircraft::HEIGHT)?;
    println!(
        "ready: taken off to {} m and in GUIDED after {ready_s:.1} s",
        aircraft::HEIGHT
    );
    let m = aircraft::measure(&mut h, MEASURED_BANK_DEG)?;
    println!(
        "the plane under roll setpoints: {}",
        m.line(MEASURED_BANK_DEG)
    );
    let mut evader = match evader_start {
        Some(starting) => Some(plane_evader::join(starting, &mut h, &mut pump)?),
        None => None,
    };
    let limits = plane_evader::law_limits(aircraft_limits(m.speed, m.curvature), evader.as_ref())?;
    let efficiency = (m.efficiency * 100.0).round() / 100.0;
    let period = (m.response * 100.0).round() / 100.0;
    println!(
        "the law: v_pm {} m/s, w_pm {} 1/m, v_em {} m/s, w_em {} 1/m; threshold {:.1} m; TC_VEHICLE 3, TC_BANK_EFF {efficiency}, TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {period:.2} s (the roll response)",
        limits[0],
        limits[1],
        limits[2],
        limits[3],
        theorem_threshold(limits),
    );
    set_unit_params(&mut h, &[("TC_VEHICLE", 3.0), ("TC_BANK_EFF", efficiency)])?;
    configure_unit(&mut h, limits, CAPTURE_RADIUS, period)?;
    h.bank_turn = (limits[0] as f32, efficiency as f32);
    let radio = options.field.then_some(Radio::AIRCRAFT);
    if let Some(radio) = radio {
        configure_field(&mut h, evader.as_mut(), radio)?;
    }
    let (outcomes, evader_speeds) = match &mut evader {
        None => (
            fly_simulated(&mut h, limits, options.short, radio)?,
            Vec::new(),
        ),
        Some(e) => fly_against_plane(&mut h, e, limits, options.short, radio)?,
    };
    drop(launched);
    Ok(Flown {
        outcomes,
        aircraft: m,
        limits,
        efficiency,
        evader_speeds,
    })
}

/// The ArduPlane SITL binary: `explicit`, else `TWOCARS_ARDUPLANE`, else
/// `../shared/ardupilot/arduplane`.
pub fn find(explicit: Option<&std::path::Path>) -> Option<PathBuf> {
    sitl::find(Frame::Plane, explicit)
}

/// The field: the unit told the radio's lag and noise; against the evader's aircraft, both
/// aircraft in the same wind, so that the game holds in the air's frame.
fn configure_field(
    h: &mut Harness,
    evader: Option<&mut plane_evader::EvaderPlane>,
    radio: Radio,
) -> Result<(), String> {
    set_unit_params(h, &radio.unit_params())?;
    let Some(evader) = evader else {
        println!("the field: {}", radio.line());
        return Ok(());
    };
    let (speed, turbulence) = WIND;
    for aircraft in [&mut *h, &mut evader.harness] {
        set_autopilot_param(aircraft, "SIM_WIND_SPD", speed)?;
        set_autopilot_param(aircraft, "SIM_WIND_TURB", turbulence)?;
    }
    println!(
        "the field: {}; both aircraft in SIM_WIND_SPD {speed} m/s, SIM_WIND_TURB {turbulence} m/s",
        radio.line()
    );
    Ok(())
}

/// The chases against the simulated evader.
fn fly_simulated(
    h: &mut Harness,
    limits: [f64; 4],
    short: bool,
    radio: Option<Radio>,
) -> Result<Vec<Outcome>, String> {
    let mut outcomes = Vec::new();
    for (i, start) in starts(limits, short).into_iter().enumerate() {
        let outcome = chase::fly(h, start, limits, CAPTURE_RADIUS, 7 + i as u64, radio)?;
        println!(
            "{}\n  {}",
            report(&outcome, limits),
            energy_line(&outcome, limits)
        );
        outcomes.push(outcome);
    }
    Ok(outcomes)
}

/// The chases against the evader's aircraft, each after the two fly apart to its distance;
/// the evader's mean ground speed over each beside them.
fn fly_against_plane(
    h: &mut Harness,
    evader: &mut plane_evader::EvaderPlane,
    limits: [f64; 4],
    short: bool,
    radio: Option<Radio>,
) -> Result<(Vec<Outcome>, Vec<f64>), String> {
    let mut steer = PlaneSteer::of(evader);
    let (mut outcomes, mut speeds) = (Vec::new(), Vec::new());
    for (i, start) in plane_evader::starts(limits, short).into_iter().enumerate() {
        let pursuer = Banked {
            limit_deg: MEASURED_BANK_DEG,
            send: &mut |h, bank| h.router.send_to_autopilot(&aircraft::roll_setpoint(bank)),
        };
        plane_evader::fly_apart(h, evader, -start.ahead, pursuer)?;
        let terms = Terms {
            eps: CAPTURE_RADIUS,
            seed: 7 + i as u64,
            field: radio,
        };
        let fixes = evader.harness.fixes.len();
        let (outcome, [peak, mean]) =
            evader::chase(h, &mut evader.harness, &mut steer, start, limits, terms)?;
        println!(
            "{}\n  {}\n  the evader's aircraft: ground speed peak {peak:.2} m/s, mean {mean:.2} m/s (v_em {} m/s); {}",
            report(&outcome, limits),
            energy_line(&outcome, limits),
            limits[2],
            crab_line(&evader.harness.fixes[fixes..])
        );
        outcomes.push(outcome);
        speeds.push(mean);
    }
    Ok((outcomes, speeds))
}

/// How far the wind turns an aircraft's yaw, which the unit steers by, off its course over
/// ground, over `fixes`: the mean and the largest, degrees.
fn crab_line(fixes: &[crate::harness::autopilot::harness::RoverFix]) -> String {
    let crabs: Vec<f64> = fixes
        .iter()
        .filter(|f| f.speed > 1.0)
        .map(|f| {
            twocars_sim::kinematics::wrap_pi(f.state[2] - f.course)
                .abs()
                .to_degrees()
        })
        .collect();
    let mean = crabs.iter().sum::<f64>() / crabs.len().max(1) as f64;
    let most = crabs.iter().copied().fold(0.0, f64::max);
    format!("its yaw (the unit's heading) off its course over ground by {mean:.1} deg on average, {most:.1} at most")
}

/// `cargo xtask run --link ardupilot --vehicle plane`; the exit code.
pub fn run(options: &Options) -> i32 {
    match fly(options) {
        Ok(flown) => i32::from(!flown.outcomes.iter().all(|o| o.captured.is_some())),
        Err(e) => {
            eprintln!("xtask run --link ardupilot --vehicle plane: {e}");
            1
        }
    }
}
