//! PX4 SITL's SIH airplane flying the pursuer under the unit's energy hold.

use crate::harness::autopilot::aircraft::chase_held;
use crate::harness::autopilot::energy_line;
use crate::harness::px4::aircraft::MEASURED_BANK_DEG;
use crate::harness::px4::find;
use crate::harness::px4::plane::{fly, Flown, Options};

/// `cargo xtask test`'s airplane chase: one start below the threshold against the straight
/// evader, where PX4 SITL is found (said plainly where not).
pub fn record(record: &mut impl FnMut(&str, Result<String, String>)) {
    println!(
        "== xtask test: PX4 SITL (SIH airplane) flying the pursuer under the unit's energy hold"
    );
    if find(None).is_none() {
        println!("   SKIPPED: PX4 SITL not found (../shared/px4/bin/px4); docs/px4.md says what to build");
        return;
    }
    let flown = fly(&Options {
        short: true,
        ..Options::default()
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
