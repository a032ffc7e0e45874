//! `cargo xtask run --link ardupilot`: a real autopilot in the loop. ArduPilot Rover SITL flies
//! the pursuer; the `twocars-qemu-mavlink` image in QEMU is its companion computer; the host is
//! the ground station, the router between them and the target: an evader of the adversary suite
//! simulated as a Dubins car and reported as system 2's GLOBAL_POSITION_INT (docs/ardupilot.md).

pub mod aircraft;
mod link;
pub mod plane;
pub mod plane_evader;
pub mod rover_evader;
mod sitl;
mod telemetry;
mod vehicle;

use sitl::Frame;

use std::path::PathBuf;
use std::time::Duration;

use twocars_sim::autopilot::HOME;

use crate::harness::autopilot::chase::{self, Outcome};
use crate::harness::autopilot::evader::Terms;
use crate::harness::autopilot::field::Radio;
use crate::harness::autopilot::harness::{Harness, NoTarget};
use crate::harness::autopilot::router::Source;
use crate::harness::autopilot::{
    configure_unit, law_limits, report, set_unit_params, starts, starts_against, Measured,
    CAPTURE_RADIUS, EVADERS, TARGET_SYSTEM,
};
use crate::image::signing::SigningKey;
use twocars_sim::sim::theorem_threshold;

/// The pursuer's speed asked of the rover (WP_SPEED: the speed at thrust 1), m/s.
const WP_SPEED: f32 = 3.0;
/// `cargo xtask run --link ardupilot`'s options.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The `ardurover` SITL binary (default: `TWOCARS_ARDUROVER`, then
    /// `../shared/ardupilot/ardurover`).
    pub ardurover: Option<PathBuf>,
    /// One short chase instead of the whole set (what `cargo xtask test` flies).
    pub short: bool,
    /// The target's fixes late, sparse and noisy ([`Radio::ROVER`]), the unit told so, and wind and
    /// GPS noise on the rover.
    pub field: bool,
    /// The chases against the simulated evader.
    pub simulated: bool,
    /// The chases against a second rover (SITL instance 1) driven by the suite's evaders.
    pub rover_evader: bool,
    /// The unit the `twocars-companion` binary on the host, not the QEMU image.
    pub companion: bool,
    /// The unit's link signed both ways with this key (ArduPilot given it with SETUP_SIGNING).
    pub key: Option<SigningKey>,
}

/// The field: the unit told the rovers' radio's lag and noise; wind and GPS noise on the
/// rover (SIM_WIND_SPD 3 m/s, SIM_GPS1_NOISE 0.5 m).
fn configure_field(h: &mut Harness) -> Result<(), String> {
    set_unit_params(h, &Radio::ROVER.unit_params())?;
    vehicle::set_autopilot_param(h, "SIM_WIND_SPD", 3.0)?;
    vehicle::set_autopilot_param(h, "SIM_GPS1_NOISE", 0.5)?;
    println!(
        "the field: {}; SIM_WIND_SPD 3 m/s, SIM_GPS1_NOISE 0.5 m",
        Radio::ROVER.line()
    );
    Ok(())
}

/// The ArduPilot Rover SITL binary: `explicit`, else `TWOCARS_ARDUROVER`, else
/// `../shared/ardupilot/ardurover`.
pub fn find_rover(explicit: Option<&std::path::Path>) -> Option<PathBuf> {
    sitl::find(Frame::Rover, explicit)
}

/// Runs the chases; the outcomes, the measured limits, the law's and the harness (for the
/// telemetry's figures).
pub fn fly(options: &Options) -> Result<Flown, String> {
    let binary = sitl::find(Frame::Rover, options.ardurover.as_deref()).ok_or(
        "ArduPilot Rover SITL not found: give --ardurover PATH or set TWOCARS_ARDUROVER \
         (docs/ardupilot.md says how to build it)",
    )?;
    let key = options.key.as_ref();
    let (launched, _sitl, router) =
        link::connect(&binary, Frame::Rover, 1, options.companion, key)?;
    let mut h = Harness::new(router, HOME, TARGET_SYSTEM);
    println!("ArduPilot Rover SITL: {}", binary.display());
    let ready = vehicle::make_ready(&mut h, WP_SPEED)?;
    println!(
        "ready: EKF using GPS after {:.1} s, GUIDED and armed after {:.1} s",
        ready.ekf_s, ready.armed_s
    );
    let probe = match h.router.signing() {
        true => Some(signing_probe(&mut h)?),
        false => None,
    };
    let measured = vehicle::measure(&mut h)?;
    let limits = law_limits(&measured);
    println!(
        "the rover, driven: {:.2} m/s at thrust 1 (WP_SPEED {WP_SPEED}), largest turn rate {:.2} rad/s, radius {:.2} m, yaw-rate response {:.2} s",
        measured.speed, measured.turn_rate, measured.radius, measured.response
    );
    println!(
        "the law: v_pm {} m/s, w_pm {} 1/m ({:.0} % of the largest turn rate), v_em {} m/s, w_em {} 1/m; threshold {:.1} m; TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {:.2} s (the yaw-rate response)",
        limits[0],
        limits[1],
        100.0 * limits[0] * limits[1] / measured.turn_rate,
        limits[2],
        limits[3],
        theorem_threshold(limits),
        (measured.response * 100.0).round() / 100.0
    );
    // The law plans each turn over the rover's yaw-rate response: planned over the 50 ms
    // between its fixes, the rate controller's lag makes the rover weave (docs/ardupilot.md).
    let period = (measured.response * 100.0).round() / 100.0;
    configure_unit(&mut h, limits, CAPTURE_RADIUS, period)?;
    if options.field {
        configure_field(&mut h)?;
    }
    let mut outcomes = Vec::new();
    if options.simulated {
        for (i, start) in starts(limits, options.short).into_iter().enumerate() {
            let seed = 7 + i as u64;
            let outcome = chase::fly(
                &mut h,
                start,
                limits,
                CAPTURE_RADIUS,
                seed,
                options.field.then_some(Radio::ROVER),
            )?;
            println!("{}", report(&outcome, limits));
            outcomes.push(outcome);
        }
    }
    if options.rover_evader {
        outcomes.extend(fly_against_rover(&mut h, &binary, limits, options)?);
    }
    let telemetry = telemetry::summary(&h);
    let signing = probe.map(|(unsigned_answered, signed_answered)| Signing {
        unsigned_answered,
        signed_answered,
        autopilot_frames: h.autopilot_signed,
        refusals: h.refusals,
    });
    drop(launched);
    // The replay image's endpoint has no key: the unsigned stream only.
    let cost = match signing {
        None => Some(crate::harness::bench::mavlink::measure_replay(
            &telemetry::write_capture(&h)?,
        )?),
        Some(_) => None,
    };
    Ok(Flown {
        outcomes,
        measured,
        limits,
        telemetry,
        cost,
        signing,
    })
}

/// The chases against the evader rover (SITL instance 1), one instance per chase.
fn fly_against_rover(
    h: &mut Harness,
    binary: &std::path::Path,
    limits: [f64; 4],
    options: &Options,
) -> Result<Vec<Outcome>, String> {
    println!(
        "the evader: a second ArduPilot Rover SITL (instance 1, WP_SPEED {} m/s), started for each chase at its start",
        limits[2]
    );
    let mut outcomes = Vec::new();
    let starts = starts_against(limits, options.short, &EVADERS);
    for (i, start) in starts.into_iter().enumerate() {
        let seed = 7 + i as u64;
        let (outcome, [peak, mean]) = rover_evader::fly(
            h,
            &mut rover_evader::pump,
            binary,
            start,
            limits,
            Terms {
                eps: CAPTURE_RADIUS,
                seed,
                field: options.field.then_some(Radio::ROVER),
            },
        )?;
        println!(
            "{}\n  the evader's rover: speed peak {peak:.2} m/s, mean {mean:.2} m/s (v_em {} m/s)",
            report(&outcome, limits),
            limits[2]
        );
        outcomes.push(outcome);
    }
    Ok(outcomes)
}

/// ArduPilot's check on the unit's link: whether an unsigned PARAM_REQUEST_READ of WP_SPEED
/// was answered (it must not be), and whether a signed one was.
fn signing_probe(h: &mut Harness) -> Result<(bool, bool), String> {
    let ask = mavlink::dialects::common::PARAM_REQUEST_READ_DATA {
        param_index: -1,
        target_system: 1,
        target_component: 1,
        param_id: "WP_SPEED".into(),
    };
    let mut answered = [false; 2];
    for (signed, slot) in [false, true].into_iter().zip(&mut answered) {
        let from = h.params.len();
        if signed {
            h.router.send_to_autopilot(&ask)?;
        } else {
            h.router.send_unsigned_to_autopilot(&ask)?;
        }
        *slot = h.pump_until(&mut NoTarget, Duration::from_millis(1500), &mut |h| {
            h.params[from..]
                .iter()
                .any(|(s, n, _)| *s == Source::Autopilot && n == "WP_SPEED")
        })?;
    }
    Ok((answered[0], answered[1]))
}

/// What a signed run showed of signing.
#[derive(Clone, Copy, Debug)]
pub struct Signing {
    /// ArduPilot answered an unsigned request on the unit's link.
    pub unsigned_answered: bool,
    /// ArduPilot answered a signed one.
    pub signed_answered: bool,
    /// ArduPilot's frames on the unit's link: signed, unsigned.
    pub autopilot_frames: (u64, u64),
    /// The unit's last TC_NOSIG, TC_BADSIG, TC_OLDSIG.
    pub refusals: [Option<f32>; 3],
}

impl std::fmt::Display for Signing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [no, bad, old] = self
            .refusals
            .map(|v| v.map_or("none".to_string(), |v| v.to_string()));
        write!(
            f,
            "signed both ways: ArduPilot {} an unsigned PARAM_REQUEST_READ on the unit's link and {} a signed one; \
             its frames there {} signed, {} unsigned; the unit refused TC_NOSIG {no}, TC_BADSIG {bad}, TC_OLDSIG {old}",
            if self.unsigned_answered { "ANSWERED" } else { "ignored" },
            if self.signed_answered { "answered" } else { "IGNORED" },
            self.autopilot_frames.0,
            self.autopilot_frames.1,
        )
    }
}

/// What `fly` flew.
pub struct Flown {
    pub outcomes: Vec<Outcome>,
    pub measured: Measured,
    pub limits: [f64; 4],
    pub telemetry: telemetry::Summary,
    /// The unit's cost on the Cortex-M4F over the run's stream (the bench's `replay` image),
    /// where unsigned.
    pub cost: Option<crate::harness::bench::mavlink::ReplayMeasured>,
    /// What the run showed of signing, where signed.
    pub signing: Option<Signing>,
}

/// The cost paragraph.
pub fn cost_line(c: &crate::harness::bench::mavlink::ReplayMeasured) -> String {
    let per_second = c.instructions / c.seconds.max(1e-9);
    format!(
        "the unit's cost on the Cortex-M4F (the whole stream replayed through its serial path in QEMU with -icount, \
         the bench's `replay` image; {} frames and {} setpoints sent, as on the host): {:.0} instructions per second \
         ({:.2} % of a 168 MHz STM32F405 at one instruction a cycle), stack {} B",
        c.frames,
        c.setpoints,
        per_second,
        100.0 * per_second / 168e6,
        c.stack
    )
}

/// `cargo xtask run --link ardupilot`; the exit code.
pub fn run(options: &Options) -> i32 {
    match fly(options) {
        Ok(flown) => {
            println!("{}", flown.telemetry);
            if let Some(cost) = &flown.cost {
                println!("{}", cost_line(cost));
            }
            if let Some(signing) = &flown.signing {
                println!("{signing}");
            }
            i32::from(!flown.outcomes.iter().all(|o| o.captured.is_some()))
        }
        Err(e) => {
            eprintln!("xtask run --link ardupilot: {e}");
            1
        }
    }
}
