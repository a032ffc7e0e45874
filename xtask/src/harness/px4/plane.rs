//! `cargo xtask run --autopilot px4 --vehicle plane`: PX4 SITL's SIH airplane flies the pursuer in
//! OFFBOARD under the unit's attitude setpoints with its own energy hold (TC_VEHICLE 4): PX4's
//! offboard attitude control takes the thrust as a throttle and holds neither airspeed nor
//! height (docs/px4.md).

use std::path::PathBuf;

use super::aircraft::{self, Held, AIRSPEED, MEASURED_BANK_DEG};
use super::sitl;
use crate::harness::ardupilot::plane_evader::{self, Banked, PlaneSteer};
use crate::harness::autopilot::chase::{self, Outcome, Start};
use crate::harness::autopilot::evader::{self, Terms};
use crate::harness::autopilot::harness::{Harness, Pursuer};
use crate::harness::autopilot::router::Router;
use crate::harness::autopilot::script::{self, Law, Vehicle};
use crate::harness::autopilot::unit::{self, Unit};
use crate::harness::autopilot::{aircraft_limits, energy_line, starts, TARGET_SYSTEM};
use twocars_sim::autopilot::HOME;

/// The SIH vehicle.
const MODEL: &str = "sihsim_airplane";
/// Capture radius, m: the SIH airplane is a model of about 1 m span; two such within 3 m
/// (GPS noise included) touch or nearly so.
pub const CAPTURE_RADIUS: f64 = 3.0;
/// A chase's time limit, s.
const CHASE_LIMIT_S: f64 = 300.0;

/// `cargo xtask run --autopilot px4 --vehicle plane`'s options.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The `px4` binary (default: `../shared/px4/bin/px4`).
    pub px4: Option<PathBuf>,
    /// One short chase instead of the whole set (what `cargo xtask test` flies).
    pub short: bool,
    /// The unit the `twocars-companion` binary on the host, not the QEMU image.
    pub companion: bool,
    /// The evader an ArduPlane SITL flown by the suite's evaders in place of the simulated
    /// one, at the wall clock's pace as PX4.
    pub plane_evader: bool,
    /// The evader's `arduplane` binary (default: as `--autopilot ardupilot` finds it).
    pub arduplane: Option<PathBuf>,
}

/// The pursuer's airspeed against the evader's aircraft, m/s: faster than against the
/// simulated evader, so that ArduPlane can fly slower; the SIH airplane's energy hold reaches
/// no more than about 14 m/s level.
const AIRSPEED_VS_PLANE: f32 = 12.0;
/// The evader's aircraft against the SIH airplane: 0.7 of its speed, ArduPlane's minimum
/// lowered to let it fly there; at the wall clock's pace, as PX4 runs here.
const EVADER: plane_evader::Spec = plane_evader::Spec {
    airspeed: 8.0,
    airspeed_min: 7.0,
    bank_deg: 15.0,
    speedup: 1,
};

/// What `fly` flew.
pub struct Flown {
    pub outcomes: Vec<Outcome>,
    pub aircraft: aircraft::Flown,
    pub limits: [f64; 4],
    pub efficiency: f64,
    /// Whether PX4 left OFFBOARD or said "failsafe" during each chase (before its end).
    pub left_offboard: Vec<bool>,
}

/// PX4's SIH airplane flying the pursuer, as the script asks: against the simulated evader, or
/// against an ArduPlane SITL flown by the suite's evaders.
struct Airplane<'a> {
    options: &'a Options,
    binary: PathBuf,
    /// The unit and PX4, running until dropped.
    running: Option<(Unit, sitl::Px4)>,
    /// The airspeed the unit's energy hold keeps, m/s.
    airspeed: f32,
    /// The evader's aircraft, starting beside the pursuer, then joined.
    evader_start: Option<std::thread::JoinHandle<Result<plane_evader::EvaderPlane, String>>>,
    evader: Option<plane_evader::EvaderPlane>,
    /// The airplane held level between chases.
    held: Held,
    aircraft: Option<aircraft::Flown>,
    efficiency: f64,
    left_offboard: Vec<bool>,
}

impl Vehicle for Airplane<'_> {
    fn start(&mut self) -> Result<Harness, String> {
        let (launched, unit) = unit::start(self.options.companion, None)?;
        let home = (f64::from(HOME.0) * 1e-7, f64::from(HOME.1) * 1e-7);
        if self.options.plane_evader {
            self.evader_start = Some(plane_evader::launch(arduplane(self.options)?, EVADER));
        }
        let (px4, link) = sitl::Px4::start(&self.binary, MODEL, 0, home)?;
        let mut h = Harness::new(Router::new(link, unit)?, HOME, TARGET_SYSTEM);
        self.running = Some((launched, px4));
        h.stop_text = "ailsafe";
        h.pursuer = Pursuer::Aircraft;
        h.chase_limit_s = CHASE_LIMIT_S;
        println!("PX4 SITL ({MODEL}): {}", self.binary.display());
        Ok(h)
    }

    fn ready(&mut self, h: &mut Harness) -> Result<String, String> {
        let ready_s = aircraft::make_ready(h)?;
        Ok(format!(
            "OFFBOARD, armed and climbed out after {ready_s:.1} s"
        ))
    }

    fn measure(&mut self, h: &mut Harness) -> Result<Law, String> {
        let airspeed = self.airspeed;
        let m = aircraft::measure(h, &mut self.held)?;
        self.aircraft = Some(m);
        println!(
            "the airplane under attitude setpoints, the energy hold at {airspeed} m/s: {:.2} m/s ground speed level; at {MEASURED_BANK_DEG} deg of bank curvature {:.4} 1/m (radius {:.1} m), {:.0} % of a coordinated turn's; roll response {:.2} s",
            m.speed,
            m.curvature,
            1.0 / m.curvature,
            100.0 * m.efficiency,
            m.response
        );
        if let Some(starting) = self.evader_start.take() {
            let held = &mut self.held;
            let mut keep = |h: &mut Harness| aircraft::fly_level(h, held, 0.0, 0.2);
            self.evader = Some(plane_evader::join(starting, h, &mut keep)?);
        }
        // TC_V_PM is also the airspeed the unit's energy hold keeps: the law's speed is the
        // airspeed held (in still air the ground speed measured).
        let limits = aircraft_limits(f64::from(airspeed), m.curvature);
        let limits = plane_evader::law_limits(limits, self.evader.as_ref())?;
        let efficiency = (m.efficiency * 100.0).round() / 100.0;
        self.efficiency = efficiency;
        let period = (m.response * 100.0).round() / 100.0;
        h.bank_turn = (airspeed, efficiency as f32);
        Ok(Law {
            limits,
            period,
            capture: CAPTURE_RADIUS,
            unit_params: vec![("TC_VEHICLE", 4.0), ("TC_BANK_EFF", efficiency)],
            note: format!(
                "TC_VEHICLE 4, TC_BANK_EFF {efficiency}, TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {period:.2} s (the roll response)"
            ),
        })
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
        aircraft::reenter_offboard(h, &mut self.held)?;
        aircraft::fly_level(h, &mut self.held, 0.0, 2.0)?;
        let (texts, modes) = (h.texts.len(), h.modes.len());
        let seed = 7 + i as u64;
        let mut notes = Vec::new();
        let outcome = match &mut self.evader {
            None => chase::fly(h, start, law.limits, CAPTURE_RADIUS, seed, None)?,
            Some(e) => {
                let (outcome, line) = chase_plane(h, &mut self.held, e, start, law.limits, seed)?;
                notes.push(line);
                outcome
            }
        };
        notes.insert(0, energy_line(&outcome, law.limits));
        self.left_offboard
            .push(super::vehicle::left_offboard(h, texts, modes, &outcome));
        Ok((outcome, notes))
    }
}

/// Runs the chases.
pub fn fly(options: &Options) -> Result<Flown, String> {
    let binary = sitl::find(options.px4.as_deref()).ok_or(
        "PX4 SITL not found: give --px4 PATH (a px4_sitl_default build with SIH, its etc/ \
         beside bin/; docs/px4.md)",
    )?;
    let airspeed = match options.plane_evader {
        true => AIRSPEED_VS_PLANE,
        false => AIRSPEED,
    };
    let mut airplane = Airplane {
        options,
        binary,
        running: None,
        airspeed,
        evader_start: None,
        evader: None,
        held: Held::new(airspeed),
        aircraft: None,
        efficiency: 0.0,
        left_offboard: Vec::new(),
    };
    let (_h, law, outcomes) = script::fly(&mut airplane)?;
    airplane.running = None;
    Ok(Flown {
        outcomes,
        aircraft: airplane.aircraft.ok_or("the airplane was not measured")?,
        limits: law.limits,
        efficiency: airplane.efficiency,
        left_offboard: airplane.left_offboard,
    })
}

/// The evader's `arduplane` binary.
fn arduplane(options: &Options) -> Result<PathBuf, String> {
    crate::harness::ardupilot::plane::find(options.arduplane.as_deref()).ok_or(
        "ArduPlane SITL not found for the evader: give --arduplane PATH or set \
         TWOCARS_ARDUPLANE (docs/ardupilot.md)"
            .to_string(),
    )
}

/// One chase against the evader's aircraft `evader`: the two flown apart to the start's
/// distance (the pursuer under `held`), then `start.evader` flies it; the outcome and the
/// evader's speeds.
fn chase_plane(
    h: &mut Harness,
    held: &mut Held,
    evader: &mut plane_evader::EvaderPlane,
    start: Start,
    limits: [f64; 4],
    seed: u64,
) -> Result<(Outcome, String), String> {
    let pursuer = Banked {
        limit_deg: MEASURED_BANK_DEG,
        send: &mut |h, bank| {
            let setpoint = aircraft::banked(h, held, bank);
            h.router.send_to_autopilot(&setpoint)
        },
    };
    plane_evader::fly_apart(h, evader, -start.ahead, pursuer)?;
    let mut steer = PlaneSteer::of(evader);
    let terms = Terms {
        eps: CAPTURE_RADIUS,
        seed,
        field: None,
    };
    let (outcome, [peak, mean]) =
        evader::chase(h, &mut evader.harness, &mut steer, start, limits, terms)?;
    let line = format!(
        "the evader's aircraft: ground speed peak {peak:.2} m/s, mean {mean:.2} m/s (v_em {} m/s)",
        limits[2]
    );
    Ok((outcome, line))
}

/// `cargo xtask run --autopilot px4 --vehicle plane`; the exit code.
pub fn run(options: &Options) -> i32 {
    match fly(options) {
        Ok(flown) => {
            let captured = flown.outcomes.iter().all(|o| o.captured.is_some());
            let clean = !flown.left_offboard.iter().any(|&f| f);
            if !clean {
                println!("PX4 left OFFBOARD during a chase");
            }
            i32::from(!(captured && clean))
        }
        Err(e) => {
            eprintln!("xtask run --autopilot px4 --vehicle plane: {e}");
            1
        }
    }
}
