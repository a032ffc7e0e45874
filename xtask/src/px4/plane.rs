//! `cargo xtask run --link px4 --vehicle plane`: PX4 SITL's SIH airplane flies the pursuer in
//! OFFBOARD under the unit's attitude setpoints with its own energy hold (TC_VEHICLE 4): PX4's
//! offboard attitude control takes the thrust as a throttle and holds neither airspeed nor
//! height (docs/px4.md).

use std::path::PathBuf;

use host_tests::autopilot::HOME;
use twocars::mavlink::energy::EnergyHold;

use super::aircraft::{self, AIRSPEED, MEASURED_BANK_DEG};
use super::sitl;
use crate::autopilot::aircraft::chase_held;
use crate::autopilot::chase::{self, Outcome};
use crate::autopilot::harness::{Harness, Pursuer};
use crate::autopilot::router::Router;
use crate::autopilot::{
    aircraft_limits, configure_unit, energy_line, report, set_unit_params, starts, threshold, unit,
    TARGET_SYSTEM,
};

/// The SIH vehicle.
const MODEL: &str = "sihsim_airplane";
/// Capture radius, m: the SIH airplane is a model of about 1 m span; two such within 3 m
/// (GPS noise included) touch or nearly so.
pub const CAPTURE_RADIUS: f64 = 3.0;
/// A chase's time limit, s.
const CHASE_LIMIT_S: f64 = 300.0;

/// `cargo xtask run --link px4 --vehicle plane`'s options.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The `px4` binary (default: `../shared/px4/bin/px4`).
    pub px4: Option<PathBuf>,
    /// One short chase instead of the whole set (what `cargo xtask test` flies).
    pub short: bool,
    /// The unit the `twocars-companion` binary on the host, not the QEMU image.
    pub companion: bool,
}

/// What `fly` flew.
pub struct Flown {
    pub outcomes: Vec<Outcome>,
    pub aircraft: aircraft::Flown,
    pub limits: [f64; 4],
    pub efficiency: f64,
    /// Whether PX4 left OFFBOARD or said "failsafe" during each chase (before its end).
    pub left_offboard: Vec<bool>,
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
    h.stop_text = "ailsafe";
    h.pursuer = Pursuer::Aircraft;
    h.chase_limit_s = CHASE_LIMIT_S;
    println!("PX4 SITL ({MODEL}): {}", binary.display());
    let ready_s = aircraft::make_ready(&mut h)?;
    println!("ready: OFFBOARD, armed and climbed out after {ready_s:.1} s");
    let mut hold = EnergyHold::new();
    let m = aircraft::measure(&mut h, &mut hold)?;
    // TC_V_PM is also the airspeed the unit's energy hold keeps: the law's speed is the
    // airspeed held (in still air the ground speed measured).
    let limits = aircraft_limits(f64::from(AIRSPEED), m.curvature);
    let efficiency = (m.efficiency * 100.0).round() / 100.0;
    let period = (m.response * 100.0).round() / 100.0;
    println!(
        "the airplane under attitude setpoints, the energy hold at {AIRSPEED} m/s: {:.2} m/s ground speed level; at {MEASURED_BANK_DEG} deg of bank curvature {:.4} 1/m (radius {:.1} m), {:.0} % of a coordinated turn's; roll response {:.2} s",
        m.speed,
        m.curvature,
        1.0 / m.curvature,
        100.0 * m.efficiency,
        m.response
    );
    println!(
        "the law: v_pm {} m/s, w_pm {} 1/m, v_em {} m/s, w_em {} 1/m; threshold {:.1} m; TC_VEHICLE 4, TC_BANK_EFF {efficiency}, TC_CAPTURE {CAPTURE_RADIUS} m, TC_PERIOD {period:.2} s (the roll response)",
        limits[0],
        limits[1],
        limits[2],
        limits[3],
        threshold(limits),
    );
    set_unit_params(&mut h, &[("TC_VEHICLE", 4.0), ("TC_BANK_EFF", efficiency)])?;
    configure_unit(&mut h, limits, CAPTURE_RADIUS, period)?;
    h.bank_turn = (AIRSPEED, efficiency as f32);
    let mut outcomes = Vec::new();
    let mut left_offboard = Vec::new();
    for (i, start) in starts(limits, options.short).into_iter().enumerate() {
        aircraft::reenter_offboard(&mut h, &mut hold)?;
        aircraft::fly_level(&mut h, &mut hold, 0.0, 2.0)?;
        let (texts, modes) = (h.texts.len(), h.modes.len());
        let outcome = chase::fly(&mut h, start, limits, CAPTURE_RADIUS, 7 + i as u64, false)?;
        println!(
            "{}\n  {}",
            report(&outcome, limits),
            energy_line(&outcome, limits)
        );
        left_offboard.push(super::left_offboard(&h, texts, modes, &outcome));
        outcomes.push(outcome);
    }
    drop(launched);
    Ok(Flown {
        outcomes,
        aircraft: m,
        limits,
        efficiency,
        left_offboard,
    })
}

/// `cargo xtask run --link px4 --vehicle plane`; the exit code.
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
            eprintln!("xtask run --link px4 --vehicle plane: {e}");
            1
        }
    }
}

/// `cargo xtask test`'s airplane chase: one start below the threshold against the straight
/// evader, where PX4 SITL is found (said plainly where not).
pub fn record_tests(record: &mut impl FnMut(&str, Result<String, String>)) {
    println!(
        "== xtask test: PX4 SITL (SIH airplane) flying the pursuer under the unit's energy hold"
    );
    if sitl::find(None).is_none() {
        println!("   SKIPPED: PX4 SITL not found (../shared/px4/bin/px4); docs/px4.md says what to build");
        return;
    }
    let flown = fly(&Options {
        px4: None,
        short: true,
        companion: false,
    });
    record(
        "px4::the_airplane_captures_holding_airspeed_and_height_through_the_unit",
        flown.as_ref().map_err(Clone::clone).and_then(check_chase),
    );
}

/// Captured no later than the ideal Dubins pursuer + 3 s, in OFFBOARD throughout; airspeed
/// within 10 % of TC_V_PM and height within a 10 m band through the chase; PX4's "Failsafe"
/// 0.9 to 1.3 s after the unit's last setpoint (COM_OF_LOSS_T 1 s).
fn check_chase(flown: &Flown) -> Result<String, String> {
    let o = flown.outcomes.first().ok_or("no chase flown")?;
    let captured = chase_held(o, flown.limits[0])?;
    let word = o.to_stop_message.ok_or("PX4 never said \"Failsafe\"")?;
    let line = format!(
        "airplane {:.2} m/s, curvature {:.4} 1/m at {MEASURED_BANK_DEG} deg ({:.0} % of coordinated), roll response {:.2} s; \
         law {:?}, TC_BANK_EFF {}; captured at {captured:.2} s (ideal {:.2} s), {} sign flips; {}; \
         PX4's failsafe {word:.2} s after the last setpoint; OFFBOARD throughout: {}",
        flown.aircraft.speed,
        flown.aircraft.curvature,
        100.0 * flown.aircraft.efficiency,
        flown.aircraft.response,
        flown.limits,
        flown.efficiency,
        o.ideal,
        o.flips,
        energy_line(o, flown.limits),
        !flown.left_offboard[0],
    );
    if !flown.left_offboard[0] && (0.9..=1.3).contains(&word) {
        Ok(line)
    } else {
        Err(line)
    }
}
