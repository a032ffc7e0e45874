//! `cargo xtask run --autopilot ardupilot --vehicle plane`: ArduPlane SITL flies the pursuer in
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
use crate::harness::autopilot::chase::{self, Outcome, Start};
use crate::harness::autopilot::evader::{self, Terms};
use crate::harness::autopilot::field::Radio;
use crate::harness::autopilot::harness::{Harness, Pursuer};
use crate::harness::autopilot::script::{self, Law, Vehicle};
use crate::harness::autopilot::unit::Unit;
use crate::harness::autopilot::{
    aircraft_limits, energy_line, set_unit_params, starts, TARGET_SYSTEM,
};

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

/// `cargo xtask run --autopilot ardupilot --vehicle plane`'s options.
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

/// ArduPlane SITL flying the pursuer, as the script asks: against the simulated evader, or
/// against a second ArduPlane flown by the suite's evaders.
struct Plane<'a> {
    options: &'a Options,
    binary: PathBuf,
    /// The unit and SITL, running until dropped.
    running: Option<(Unit, sitl::Sitl)>,
    /// The evader's aircraft, starting beside the pursuer, then joined.
    evader_start: Option<std::thread::JoinHandle<Result<plane_evader::EvaderPlane, String>>>,
    evader: Option<plane_evader::EvaderPlane>,
    aircraft: Option<aircraft::Flown>,
    efficiency: f64,
    /// Against the evader's aircraft: its mean ground speed over each chase, m/s.
    evader_speeds: Vec<f64>,
}

impl Vehicle for Plane<'_> {
    fn start(&mut self) -> Result<Harness, String> {
        let o = self.options;
        let (unit, sitl, router) = super::link::connect(
            &self.binary,
            Frame::Plane,
            o.speedup,
            o.companion,
            o.key.as_ref(),
        )?;
        self.running = Some((unit, sitl));
        self.evader_start = o.plane_evader.then(|| {
            plane_evader::launch(
                self.binary.clone(),
                plane_evader::Spec {
                    speedup: o.speedup,
                    ..plane_evader::AGAINST_ARDUPLANE
                },
            )
        });
        let mut h = Harness::new(router, HOME, TARGET_SYSTEM);
        h.pursuer = Pursuer::Aircraft;
        h.chase_limit_s = CHASE_LIMIT_S;
        println!(
            "ArduPlane SITL at {}x the wall clock: {}",
            o.speedup,
            self.binary.display()
        );
        Ok(h)
    }

    fn ready(&mut self, h: &mut Harness) -> Result<String, String> {
        let ready_s = aircraft::make_ready(h, aircraft::HEIGHT)?;
        Ok(format!(
            "taken off to {} m and in GUIDED after {ready_s:.1} s",
            aircraft::HEIGHT
        ))
    }

    fn measure(&mut self, h: &mut Harness) -> Result<Law, String> {
        let m = aircraft::measure(h, MEASURED_BANK_DEG)?;
        self.aircraft = Some(m);
        println!(
            "the plane under roll setpoints: {}",
            m.line(MEASURED_BANK_DEG)
        );
        if let Some(starting) = self.evader_start.take() {
            self.evader = Some(plane_evader::join(starting, h, &mut pump)?);
        }
        let limits = aircraft_limits(m.speed, m.curvature);
        let limits = plane_evader::law_limits(limits, self.evader.as_ref())?;
        let efficiency = (m.efficiency * 100.0).round() / 100.0;
        self.efficiency = efficiency;
        let period = (m.response * 100.0).round() / 100.0;
        h.bank_turn = (limits[0] as f32, efficiency as f32);
        Ok(Law {
            limits,
            period,
            capture: CAPTURE_RADIUS,
            unit_params: vec![("TC_VEHICLE", 3.0), ("TC_BANK_EFF", efficiency)],
            note: format!(
                "TC_VEHICLE 3, TC_BANK_EFF {efficiency}, TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {period:.2} s (the roll response)"
            ),
        })
    }

    fn configure(&mut self, h: &mut Harness, _law: &Law) -> Result<(), String> {
        match self.options.field {
            true => configure_field(h, self.evader.as_mut(), Radio::AIRCRAFT),
            false => Ok(()),
        }
    }

    fn starts(&mut self, law: &Law) -> Vec<Start> {
        match self.evader {
            None => starts(law.limits, self.options.short),
            Some(_) => plane_evader::starts(law.limits, self.options.short),
        }
    }

    fn chase(
        &mut self,
        h: &mut Harness,
        i: usize,
        start: Start,
        law: &Law,
    ) -> Result<(Outcome, Vec<String>), String> {
        let radio = self.options.field.then_some(Radio::AIRCRAFT);
        let seed = 7 + i as u64;
        let Some(evader) = &mut self.evader else {
            let outcome = chase::fly(h, start, law.limits, CAPTURE_RADIUS, seed, radio)?;
            let energy = energy_line(&outcome, law.limits);
            return Ok((outcome, vec![energy]));
        };
        let pursuer = Banked {
            limit_deg: MEASURED_BANK_DEG,
            send: &mut |h, bank| h.router.send_to_autopilot(&aircraft::roll_setpoint(bank)),
        };
        plane_evader::fly_apart(h, evader, -start.ahead, pursuer)?;
        let terms = Terms {
            eps: CAPTURE_RADIUS,
            seed,
            field: radio,
        };
        let fixes = evader.harness.fixes.len();
        let mut steer = PlaneSteer::of(evader);
        let (outcome, [peak, mean]) =
            evader::chase(h, &mut evader.harness, &mut steer, start, law.limits, terms)?;
        self.evader_speeds.push(mean);
        let notes = vec![
            energy_line(&outcome, law.limits),
            format!(
                "the evader's aircraft: ground speed peak {peak:.2} m/s, mean {mean:.2} m/s (v_em {} m/s); {}",
                law.limits[2],
                crab_line(&evader.harness.fixes[fixes..])
            ),
        ];
        Ok((outcome, notes))
    }
}

/// Runs the chases.
pub fn fly(options: &Options) -> Result<Flown, String> {
    let binary = sitl::find(Frame::Plane, options.arduplane.as_deref()).ok_or(
        "ArduPlane SITL not found: give --arduplane PATH or set TWOCARS_ARDUPLANE \
         (docs/ardupilot.md says how to build it)",
    )?;
    let mut plane = Plane {
        options,
        binary,
        running: None,
        evader_start: None,
        evader: None,
        aircraft: None,
        efficiency: 0.0,
        evader_speeds: Vec::new(),
    };
    let (_h, law, outcomes) = script::fly(&mut plane)?;
    plane.running = None;
    Ok(Flown {
        outcomes,
        aircraft: plane.aircraft.ok_or("the plane was not measured")?,
        limits: law.limits,
        efficiency: plane.efficiency,
        evader_speeds: plane.evader_speeds,
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

/// `cargo xtask run --autopilot ardupilot --vehicle plane`; the exit code.
pub fn run(options: &Options) -> i32 {
    match fly(options) {
        Ok(flown) => i32::from(!flown.outcomes.iter().all(|o| o.captured.is_some())),
        Err(e) => {
            eprintln!("xtask run --autopilot ardupilot --vehicle plane: {e}");
            1
        }
    }
}
