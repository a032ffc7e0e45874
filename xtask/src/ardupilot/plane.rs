//! `cargo xtask run --link ardupilot --vehicle plane`: ArduPlane SITL flies the pursuer in
//! GUIDED, the unit's roll-only attitude setpoints (TC_VEHICLE 3) turning it while ArduPlane's
//! TECS holds airspeed and height; the target an evader of the adversary suite simulated as a
//! Dubins car at the law's evader limits (docs/ardupilot.md).

use std::path::PathBuf;

use host_tests::autopilot::HOME;

use super::aircraft::{self, MEASURED_BANK_DEG};
use super::sitl::{self, Frame};
use crate::autopilot::aircraft::chase_held;
use crate::autopilot::chase::{self, Outcome};
use crate::autopilot::harness::{Harness, Pursuer};
use crate::autopilot::{
    aircraft_limits, configure_unit, energy_line, report, set_unit_params, starts, threshold,
    TARGET_SYSTEM,
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
}

/// What `fly` flew.
pub struct Flown {
    pub outcomes: Vec<Outcome>,
    pub aircraft: aircraft::Flown,
    pub limits: [f64; 4],
    /// TC_BANK_EFF as set.
    pub efficiency: f64,
}

/// Runs the chases.
pub fn fly(options: &Options) -> Result<Flown, String> {
    let binary = sitl::find(Frame::Plane, options.arduplane.as_deref()).ok_or(
        "ArduPlane SITL not found: give --arduplane PATH or set TWOCARS_ARDUPLANE \
         (docs/ardupilot.md says how to build it)",
    )?;
    let (launched, _sitl, router) =
        super::connect(&binary, Frame::Plane, options.speedup, options.companion)?;
    let mut h = Harness::new(router, HOME, TARGET_SYSTEM);
    h.pursuer = Pursuer::Aircraft;
    h.chase_limit_s = CHASE_LIMIT_S;
    println!(
        "ArduPlane SITL at {}x the wall clock: {}",
        options.speedup,
        binary.display()
    );
    let ready_s = aircraft::make_ready(&mut h)?;
    println!(
        "ready: taken off to {} m and in GUIDED after {ready_s:.1} s",
        aircraft::HEIGHT
    );
    let m = aircraft::measure(&mut h)?;
    let limits = aircraft_limits(m.speed, m.curvature);
    let efficiency = (m.efficiency * 100.0).round() / 100.0;
    let period = (m.response * 100.0).round() / 100.0;
    println!(
        "the plane under roll setpoints: {:.2} m/s ground speed level, airspeed {:.2} m/s; at {MEASURED_BANK_DEG} deg of bank curvature {:.5} 1/m (radius {:.1} m), {:.0} % of a coordinated turn's; roll response {:.2} s",
        m.speed,
        m.airspeed,
        m.curvature,
        1.0 / m.curvature,
        100.0 * m.efficiency,
        m.response
    );
    println!(
        "the law: v_pm {} m/s, w_pm {} 1/m, v_em {} m/s, w_em {} 1/m; threshold {:.1} m; TC_VEHICLE 3, TC_BANK_EFF {efficiency}, TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {period:.2} s (the roll response)",
        limits[0],
        limits[1],
        limits[2],
        limits[3],
        threshold(limits),
    );
    set_unit_params(&mut h, &[("TC_VEHICLE", 3.0), ("TC_BANK_EFF", efficiency)])?;
    configure_unit(&mut h, limits, CAPTURE_RADIUS, period)?;
    h.bank_turn = (limits[0] as f32, efficiency as f32);
    let mut outcomes = Vec::new();
    for (i, start) in starts(limits, options.short).into_iter().enumerate() {
        let outcome = chase::fly(&mut h, start, limits, CAPTURE_RADIUS, 7 + i as u64, false)?;
        println!(
            "{}\n  {}",
            report(&outcome, limits),
            energy_line(&outcome, limits)
        );
        outcomes.push(outcome);
    }
    drop(launched);
    Ok(Flown {
        outcomes,
        aircraft: m,
        limits,
        efficiency,
    })
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

/// `cargo xtask test`'s plane chase: one start below the threshold against the straight
/// evader, where ArduPlane SITL is found (said plainly where not).
pub fn record_tests(record: &mut impl FnMut(&str, Result<String, String>)) {
    println!("== xtask test: ArduPlane SITL flying the pursuer in GUIDED, the MAVLink image its companion");
    if sitl::find(Frame::Plane, None).is_none() {
        println!(
            "   SKIPPED: ArduPlane SITL not found (TWOCARS_ARDUPLANE or \
             ../shared/ardupilot/arduplane); docs/ardupilot.md says how to build it"
        );
        return;
    }
    let flown = fly(&Options {
        arduplane: None,
        short: true,
        companion: false,
        speedup: SPEEDUP,
    });
    record(
        "ardupilot::arduplane_captures_under_roll_setpoints_holding_airspeed_and_height",
        flown.as_ref().map_err(Clone::clone).and_then(check_chase),
    );
}

/// Captured no later than the ideal Dubins pursuer + 3 s with at most 5 sign flips; airspeed
/// within 10 % of TC_V_PM and height within 10 m of the start's through the chase; ArduPlane's
/// own roll back 2.9 to 3.3 s after the unit's last setpoint (its fixed 3 s timeout).
fn check_chase(flown: &Flown) -> Result<String, String> {
    let o = flown.outcomes.first().ok_or("no chase flown")?;
    let captured = chase_held(o, flown.limits[0])?;
    let failsafe = o.to_failsafe.ok_or("ArduPlane never took its roll back")?;
    let line = format!(
        "plane {:.2} m/s, curvature {:.5} 1/m at {MEASURED_BANK_DEG} deg ({:.0} % of coordinated), roll response {:.2} s; \
         law {:?}, TC_BANK_EFF {}; captured at {captured:.2} s (ideal {:.2} s), {} sign flips; {}; \
         ArduPlane's own roll {failsafe:.2} s after the last setpoint",
        flown.aircraft.speed,
        flown.aircraft.curvature,
        100.0 * flown.aircraft.efficiency,
        flown.aircraft.response,
        flown.limits,
        flown.efficiency,
        o.ideal,
        o.flips,
        energy_line(o, flown.limits),
    );
    if o.flips <= 5 && (2.9..=3.3).contains(&failsafe) {
        Ok(line)
    } else {
        Err(line)
    }
}
