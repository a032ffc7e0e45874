//! `cargo xtask run --autopilot px4`: PX4 SITL (its SIH simulator, no Gazebo) flies the pursuer, an
//! Ackermann rover in OFFBOARD driven by the unit's velocity setpoints (TC_VEHICLE 2); the unit
//! is the `twocars-qemu-mavlink` image in QEMU or the `twocars-companion` binary; the host is the
//! ground station, the router on PX4's offboard UDP link, and the target: an evader of the
//! adversary suite simulated as a Dubins car, reported as system 2's GLOBAL_POSITION_INT
//! (docs/px4.md).

pub mod aircraft;
pub mod plane;
mod sitl;

pub use sitl::find;
mod vehicle;

use std::path::PathBuf;

use twocars_sim::autopilot::HOME;

use crate::harness::autopilot::chase::{self, Outcome, Start};
use crate::harness::autopilot::evader::Terms;
use crate::harness::autopilot::harness::Harness;
use crate::harness::autopilot::router::Router;
use crate::harness::autopilot::script::{self, Law, Vehicle};
use crate::harness::autopilot::unit::{self, Unit};
use crate::harness::autopilot::{
    law_limits, starts_against, Measured, CAPTURE_RADIUS, EVADERS, TARGET_SYSTEM,
};

/// The speed asked of the rover, m/s: under the SIH rover's 3 m/s limit, with room for its
/// speed controller.
const SPEED: f64 = 2.5;
/// The SIH vehicle.
const MODEL: &str = "sihsim_rover_ackermann";

/// `cargo xtask run --autopilot px4`'s options.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The `px4` binary (default: `../shared/px4/bin/px4`, its `etc/` beside `bin/`).
    pub px4: Option<PathBuf>,
    /// One short chase instead of the whole set (what `cargo xtask test` flies).
    pub short: bool,
    /// The unit the `twocars-companion` binary on the host, not the QEMU image.
    pub companion: bool,
    /// The evader an ArduPilot Rover SITL driven by the suite's evaders in place of the
    /// simulated one.
    pub rover_evader: bool,
    /// The evader's `ardurover` binary (default: as `--autopilot ardupilot` finds it).
    pub ardurover: Option<PathBuf>,
}

/// What `fly` flew.
pub struct Flown {
    pub outcomes: Vec<Outcome>,
    pub measured: Measured,
    pub limits: [f64; 4],
    /// Whether PX4 left OFFBOARD or said "failsafe" during a chase (before its end).
    pub failsafe_in_chase: Vec<bool>,
}

/// PX4's SIH rover flying the pursuer, as the script asks: against the simulated evader, or
/// against an ArduPilot Rover SITL driven by the suite's evaders.
struct Rover<'a> {
    options: &'a Options,
    binary: PathBuf,
    /// The unit and PX4, running until dropped.
    running: Option<(Unit, sitl::Px4)>,
    measured: Option<Measured>,
    /// The evader's `ardurover` binary, where a rover is the evader.
    evader: Option<PathBuf>,
    failsafe_in_chase: Vec<bool>,
}

impl Vehicle for Rover<'_> {
    fn start(&mut self) -> Result<Harness, String> {
        let (launched, unit) = unit::start(self.options.companion, None)?;
        let home = (f64::from(HOME.0) * 1e-7, f64::from(HOME.1) * 1e-7);
        let (px4, link) = sitl::Px4::start(&self.binary, MODEL, 0, home)?;
        let mut h = Harness::new(Router::new(link, unit)?, HOME, TARGET_SYSTEM);
        self.running = Some((launched, px4));
        h.stop_text = vehicle::STOP_TEXT;
        println!("PX4 SITL ({MODEL}): {}", self.binary.display());
        Ok(h)
    }

    fn ready(&mut self, h: &mut Harness) -> Result<String, String> {
        let ready_s = vehicle::make_ready(h)?;
        Ok(format!(
            "a position, OFFBOARD and armed after {ready_s:.1} s"
        ))
    }

    fn measure(&mut self, h: &mut Harness) -> Result<Law, String> {
        let measured = vehicle::measure(h, SPEED)?;
        self.measured = Some(measured);
        let period = (measured.response * 100.0).round() / 100.0;
        println!(
            "the rover, driven by velocity setpoints of {SPEED} m/s: {:.2} m/s, largest turn rate {:.2} rad/s, radius {:.2} m, heading response {:.2} s",
            measured.speed, measured.turn_rate, measured.radius, measured.response
        );
        h.period = period as f32;
        Ok(Law {
            limits: law_limits(&measured),
            period,
            capture: CAPTURE_RADIUS,
            unit_params: vec![("TC_VEHICLE", 2.0)],
            note: format!(
                "TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {period:.2} s (the heading response), TC_VEHICLE 2"
            ),
        })
    }

    fn configure(&mut self, _h: &mut Harness, law: &Law) -> Result<(), String> {
        if self.options.rover_evader {
            self.evader = Some(evader_rover(self.options.ardurover.as_deref(), law.limits)?);
        }
        Ok(())
    }

    fn starts(&mut self, law: &Law) -> Vec<Start> {
        let evaders = match self.evader {
            Some(_) => &EVADERS[..],
            None => &EVADERS[..3],
        };
        starts_against(law.limits, self.options.short, evaders)
    }

    fn chase(
        &mut self,
        h: &mut Harness,
        i: usize,
        start: Start,
        law: &Law,
    ) -> Result<(Outcome, Vec<String>), String> {
        vehicle::enter_offboard(h, &mut |h, s| vehicle::hold(h, s))?;
        vehicle::hold(h, 1.0)?;
        let (texts, modes) = (h.texts.len(), h.modes.len());
        let seed = 7 + i as u64;
        let (outcome, notes) = match &self.evader {
            None => (
                chase::fly(h, start, law.limits, CAPTURE_RADIUS, seed, None)?,
                Vec::new(),
            ),
            Some(binary) => {
                // PX4 leaves OFFBOARD a second after the last setpoint: the ground station
                // holds the rover while the evader starts.
                let terms = Terms {
                    eps: CAPTURE_RADIUS,
                    seed,
                    field: None,
                };
                let (outcome, [peak, mean]) = crate::harness::ardupilot::rover_evader::fly(
                    h,
                    &mut |h| vehicle::hold(h, 0.2),
                    binary,
                    start,
                    law.limits,
                    terms,
                )?;
                let line = format!(
                    "the evader's rover: speed peak {peak:.2} m/s, mean {mean:.2} m/s (v_em {} m/s)",
                    law.limits[2]
                );
                (outcome, vec![line])
            }
        };
        self.failsafe_in_chase
            .push(vehicle::left_offboard(h, texts, modes, &outcome));
        Ok((outcome, notes))
    }
}

/// Runs the chases.
pub fn fly(options: &Options) -> Result<Flown, String> {
    let binary = sitl::find(options.px4.as_deref()).ok_or(
        "PX4 SITL not found: give --px4 PATH (a px4_sitl_default build with SIH, its etc/ \
         beside bin/; docs/px4.md)",
    )?;
    let mut rover = Rover {
        options,
        binary,
        running: None,
        measured: None,
        evader: None,
        failsafe_in_chase: Vec::new(),
    };
    let (_h, law, outcomes) = script::fly(&mut rover)?;
    rover.running = None;
    Ok(Flown {
        outcomes,
        measured: rover.measured.ok_or("the rover was not measured")?,
        limits: law.limits,
        failsafe_in_chase: rover.failsafe_in_chase,
    })
}

/// The ArduPilot Rover SITL binary for the evader (`explicit`, else where `--autopilot ardupilot`
/// looks), said with the evader's limits.
fn evader_rover(explicit: Option<&std::path::Path>, limits: [f64; 4]) -> Result<PathBuf, String> {
    let binary = crate::harness::ardupilot::find_rover(explicit).ok_or(
        "ArduPilot Rover SITL not found for the evader: give --ardurover PATH or set \
         TWOCARS_ARDUROVER (docs/ardupilot.md)",
    )?;
    println!(
        "the evader: ArduPilot Rover SITL (instance 1, WP_SPEED {} m/s), started for each chase at its start: {}",
        limits[2],
        binary.display()
    );
    Ok(binary)
}

/// `cargo xtask run --autopilot px4`; the exit code.
pub fn run(options: &Options) -> i32 {
    match fly(options) {
        Ok(flown) => {
            let captured = flown.outcomes.iter().all(|o| o.captured.is_some());
            let clean = !flown.failsafe_in_chase.iter().any(|&f| f);
            if !clean {
                println!("PX4 left OFFBOARD during a chase");
            }
            i32::from(!(captured && clean))
        }
        Err(e) => {
            eprintln!("xtask run --autopilot px4: {e}");
            1
        }
    }
}
