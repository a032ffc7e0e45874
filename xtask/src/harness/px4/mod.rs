//! `cargo xtask run --link px4`: PX4 SITL (its SIH simulator, no Gazebo) flies the pursuer, an
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

use crate::harness::autopilot::chase::{self, Outcome};
use crate::harness::autopilot::evader::Terms;
use crate::harness::autopilot::harness::Harness;
use crate::harness::autopilot::router::Router;
use crate::harness::autopilot::{
    configure_unit, law_limits, report, set_unit_params, starts_against, unit, Measured,
    CAPTURE_RADIUS, EVADERS, TARGET_SYSTEM,
};
use twocars_sim::sim::theorem_threshold;

/// The speed asked of the rover, m/s: under the SIH rover's 3 m/s limit, with room for its
/// speed controller.
const SPEED: f64 = 2.5;
/// The SIH vehicle.
const MODEL: &str = "sihsim_rover_ackermann";

/// `cargo xtask run --link px4`'s options.
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
    /// The evader's `ardurover` binary (default: as `--link ardupilot` finds it).
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

/// Runs the chases.
pub fn fly(options: &Options) -> Result<Flown, String> {
    let binary = sitl::find(options.px4.as_deref()).ok_or(
        "PX4 SITL not found: give --px4 PATH (a px4_sitl_default build with SIH, its etc/ \
         beside bin/; docs/px4.md)",
    )?;
    let (launched, unit) = unit::start(options.companion, None)?;
    let home = (f64::from(HOME.0) * 1e-7, f64::from(HOME.1) * 1e-7);
    let (_px4, link) = sitl::Px4::start(&binary, MODEL, 0, home)?;
    let mut h = Harness::new(Router::new(link, unit)?, HOME, TARGET_SYSTEM);
    h.stop_text = vehicle::STOP_TEXT;
    println!("PX4 SITL ({MODEL}): {}", binary.display());
    let ready_s = vehicle::make_ready(&mut h)?;
    println!("ready: a position, OFFBOARD and armed after {ready_s:.1} s");
    let measured = vehicle::measure(&mut h, SPEED)?;
    let limits = law_limits(&measured);
    let period = (measured.response * 100.0).round() / 100.0;
    println!(
        "the rover, driven by velocity setpoints of {SPEED} m/s: {:.2} m/s, largest turn rate {:.2} rad/s, radius {:.2} m, heading response {:.2} s",
        measured.speed, measured.turn_rate, measured.radius, measured.response
    );
    println!(
        "the law: v_pm {} m/s, w_pm {} 1/m, v_em {} m/s, w_em {} 1/m; threshold {:.1} m; TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {period:.2} s (the heading response), TC_VEHICLE 2",
        limits[0],
        limits[1],
        limits[2],
        limits[3],
        theorem_threshold(limits),
    );
    set_unit_params(&mut h, &[("TC_VEHICLE", 2.0)])?;
    configure_unit(&mut h, limits, CAPTURE_RADIUS, period)?;
    h.period = period as f32;
    let mut outcomes = Vec::new();
    let mut failsafe_in_chase = Vec::new();
    let evader = match options.rover_evader {
        false => None,
        true => Some(evader_rover(options.ardurover.as_deref(), limits)?),
    };
    let evaders = if evader.is_some() {
        &EVADERS[..]
    } else {
        &EVADERS[..3]
    };
    for (i, start) in starts_against(limits, options.short, evaders)
        .into_iter()
        .enumerate()
    {
        vehicle::enter_offboard(&mut h, &mut |h, s| vehicle::hold(h, s))?;
        vehicle::hold(&mut h, 1.0)?;
        let texts = h.texts.len();
        let modes = h.modes.len();
        let seed = 7 + i as u64;
        let outcome = match &evader {
            None => chase::fly(&mut h, start, limits, CAPTURE_RADIUS, seed, None)?,
            Some(binary) => {
                // PX4 leaves OFFBOARD a second after the last setpoint: the ground station
                // holds the rover while the evader starts.
                let (outcome, [peak, mean]) = crate::harness::ardupilot::rover_evader::fly(
                    &mut h,
                    &mut |h| vehicle::hold(h, 0.2),
                    binary,
                    start,
                    limits,
                    Terms {
                        eps: CAPTURE_RADIUS,
                        seed,
                        field: None,
                    },
                )?;
                println!(
                    "the evader's rover: speed peak {peak:.2} m/s, mean {mean:.2} m/s (v_em {} m/s)",
                    limits[2]
                );
                outcome
            }
        };
        println!("{}", report(&outcome, limits));
        failsafe_in_chase.push(vehicle::left_offboard(&h, texts, modes, &outcome));
        outcomes.push(outcome);
    }
    drop(launched);
    Ok(Flown {
        outcomes,
        measured,
        limits,
        failsafe_in_chase,
    })
}

/// The ArduPilot Rover SITL binary for the evader (`explicit`, else where `--link ardupilot`
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

/// `cargo xtask run --link px4`; the exit code.
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
            eprintln!("xtask run --link px4: {e}");
            1
        }
    }
}
