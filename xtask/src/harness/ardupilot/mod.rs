//! `cargo xtask run --autopilot ardupilot`: a real autopilot in the loop. ArduPilot Rover SITL flies
//! the pursuer; the `twocars-qemu-mavlink` image in QEMU is its companion computer; the host is
//! the ground station, the router between them and the target: an evader of the adversary suite
//! simulated as a Dubins car and reported as system 2's GLOBAL_POSITION_INT (docs/ardupilot.md).

pub mod aircraft;
mod link;
pub mod plane;
pub mod plane_evader;
pub mod rover_evader;
mod sitl;
pub mod team;
mod telemetry;
mod vehicle;

use sitl::Frame;

use std::path::PathBuf;
use std::time::Duration;

use twocars_sim::autopilot::HOME;

use crate::harness::autopilot::chase::{self, Outcome, Start};
use crate::harness::autopilot::evader::Terms;
use crate::harness::autopilot::field::Radio;
use crate::harness::autopilot::harness::{Harness, NoTarget};
use crate::harness::autopilot::router::Source;
use crate::harness::autopilot::script::{self, Law, Vehicle};
use crate::harness::autopilot::unit::Unit;
use crate::harness::autopilot::{
    law_limits, set_unit_params, starts, starts_against, Measured, CAPTURE_RADIUS, EVADERS,
    TARGET_SYSTEM,
};
use crate::image::signing::SigningKey;

/// The pursuer's speed asked of the rover (WP_SPEED: the speed at thrust 1), m/s.
const WP_SPEED: f32 = 3.0;
/// `cargo xtask run --autopilot ardupilot`'s options.
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

/// ArduPilot Rover SITL flying the pursuer, as the script asks: the simulated evader's chases,
/// then those against the evader's rover.
struct Rover<'a> {
    options: &'a Options,
    binary: PathBuf,
    /// The unit and SITL, running until dropped.
    running: Option<(Unit, sitl::Sitl)>,
    /// ArduPilot's answers to an unsigned and a signed request, where signed.
    probe: Option<(bool, bool)>,
    measured: Option<Measured>,
    /// How many of the starts are the simulated evader's.
    simulated: usize,
}

impl Vehicle for Rover<'_> {
    fn start(&mut self) -> Result<Harness, String> {
        let o = self.options;
        let (unit, sitl, router) =
            link::connect(&self.binary, Frame::Rover, 1, o.companion, o.key.as_ref())?;
        self.running = Some((unit, sitl));
        println!("ArduPilot Rover SITL: {}", self.binary.display());
        Ok(Harness::new(router, HOME, TARGET_SYSTEM))
    }

    fn ready(&mut self, h: &mut Harness) -> Result<String, String> {
        let ready = vehicle::make_ready(h, WP_SPEED)?;
        if h.router.signing() {
            self.probe = Some(signing_probe(h)?);
        }
        Ok(format!(
            "EKF using GPS after {:.1} s, GUIDED and armed after {:.1} s",
            ready.ekf_s, ready.armed_s
        ))
    }

    fn measure(&mut self, h: &mut Harness) -> Result<Law, String> {
        let measured = vehicle::measure(h)?;
        self.measured = Some(measured);
        let limits = law_limits(&measured);
        println!(
            "the rover, driven: {:.2} m/s at thrust 1 (WP_SPEED {WP_SPEED}), largest turn rate {:.2} rad/s, radius {:.2} m, yaw-rate response {:.2} s",
            measured.speed, measured.turn_rate, measured.radius, measured.response
        );
        // The law plans each turn over the rover's yaw-rate response: planned over the 50 ms
        // between its fixes, the rate controller's lag makes the rover weave (docs/ardupilot.md).
        let period = (measured.response * 100.0).round() / 100.0;
        Ok(Law {
            limits,
            period,
            capture: CAPTURE_RADIUS,
            unit_params: Vec::new(),
            note: format!(
                "w_pm {:.0} % of the largest turn rate; TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {period:.2} s (the yaw-rate response)",
                100.0 * limits[0] * limits[1] / measured.turn_rate,
            ),
        })
    }

    fn configure(&mut self, h: &mut Harness, _law: &Law) -> Result<(), String> {
        match self.options.field {
            true => configure_field(h),
            false => Ok(()),
        }
    }

    fn starts(&mut self, law: &Law) -> Vec<Start> {
        let o = self.options;
        let mut all = match o.simulated {
            true => starts(law.limits, o.short),
            false => Vec::new(),
        };
        self.simulated = all.len();
        if o.rover_evader {
            all.extend(starts_against(law.limits, o.short, &EVADERS));
        }
        all
    }

    fn chase(
        &mut self,
        h: &mut Harness,
        i: usize,
        start: Start,
        law: &Law,
    ) -> Result<(Outcome, Vec<String>), String> {
        let radio = self.options.field.then_some(Radio::ROVER);
        let Some(k) = i.checked_sub(self.simulated) else {
            let outcome = chase::fly(h, start, law.limits, CAPTURE_RADIUS, 7 + i as u64, radio)?;
            return Ok((outcome, Vec::new()));
        };
        if k == 0 {
            println!(
                "the evader: a second ArduPilot Rover SITL (instance 1, WP_SPEED {} m/s), started for each chase at its start",
                law.limits[2]
            );
        }
        let terms = Terms {
            eps: CAPTURE_RADIUS,
            seed: 7 + k as u64,
            field: radio,
        };
        let (outcome, [peak, mean]) = rover_evader::fly(
            h,
            &mut rover_evader::pump,
            &self.binary,
            start,
            law.limits,
            terms,
        )?;
        let line = format!(
            "the evader's rover: speed peak {peak:.2} m/s, mean {mean:.2} m/s (v_em {} m/s)",
            law.limits[2]
        );
        Ok((outcome, vec![line]))
    }
}

/// Runs the chases; the outcomes, the measured limits, the law's and the harness (for the
/// telemetry's figures).
pub fn fly(options: &Options) -> Result<Flown, String> {
    let binary = sitl::find(Frame::Rover, options.ardurover.as_deref()).ok_or(
        "ArduPilot Rover SITL not found: give --ardurover PATH or set TWOCARS_ARDUROVER \
         (docs/ardupilot.md says how to build it)",
    )?;
    let mut rover = Rover {
        options,
        binary,
        running: None,
        probe: None,
        measured: None,
        simulated: 0,
    };
    let (h, law, outcomes) = script::fly(&mut rover)?;
    let telemetry = telemetry::summary(&h);
    let signing = rover
        .probe
        .map(|(unsigned_answered, signed_answered)| Signing {
            unsigned_answered,
            signed_answered,
            autopilot_frames: h.autopilot_signed,
            refusals: h.refusals,
        });
    // The unit and SITL stop before the replay's QEMU starts; its endpoint has no key: the
    // unsigned stream only.
    rover.running = None;
    let cost = match signing {
        None => Some(crate::harness::bench::mavlink::measure_replay(
            &telemetry::write_capture(&h)?,
        )?),
        Some(_) => None,
    };
    Ok(Flown {
        outcomes,
        measured: rover.measured.ok_or("the rover was not measured")?,
        limits: law.limits,
        telemetry,
        cost,
        signing,
    })
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

/// `cargo xtask run --autopilot ardupilot`; the exit code.
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
            eprintln!("xtask run --autopilot ardupilot: {e}");
            1
        }
    }
}
