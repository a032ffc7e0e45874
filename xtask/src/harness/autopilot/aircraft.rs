//! What both autopilots' aircraft share: a roll step read off the harness's records (the
//! steady turn over its second half, the roll's response), and the checks of an aircraft's
//! chase (on time, airspeed and height held).

use super::chase::Outcome;
use super::harness::Harness;

/// Where the harness's records stood when a roll step began, and the aircraft's time then.
#[derive(Clone, Copy, Debug)]
pub struct StepMarks {
    fixes: usize,
    rolls: usize,
    start_ms: u32,
}

impl StepMarks {
    pub fn now(h: &Harness) -> StepMarks {
        StepMarks {
            fixes: h.fixes.len(),
            rolls: h.rolls.len(),
            start_ms: h.now_ms(),
        }
    }
}

/// A roll step of `seconds` to `bank_deg`, as flown since `marks`: the mean ground speed
/// (m/s) and heading rate (rad/s, clockwise) over its second half, and the roll's time to 63 %
/// of the step (s; NaN for a step to level).
pub fn read_step(h: &Harness, marks: StepMarks, bank_deg: f64, seconds: f64) -> (f64, f64, f64) {
    let half = marks.start_ms + (seconds * 500.0) as u32;
    let settled: Vec<_> = h.fixes[marks.fixes..]
        .iter()
        .filter(|f| f.time_ms >= half)
        .collect();
    let turned: f64 = settled
        .windows(2)
        .map(|w| twocars_sim::kinematics::wrap_pi(w[1].state[2] - w[0].state[2]))
        .sum();
    let span = match (settled.first(), settled.last()) {
        (Some(a), Some(b)) => f64::from(b.time_ms.wrapping_sub(a.time_ms)) / 1000.0,
        _ => 0.0,
    };
    let speed = settled.iter().map(|f| f.speed).sum::<f64>() / settled.len().max(1) as f64;
    let target = bank_deg.to_radians();
    let response = h.rolls[marks.rolls..]
        .iter()
        .find(|(_, r)| f64::from(*r) * target.signum() >= 0.63 * target.abs())
        .map_or(f64::NAN, |(t, _)| {
            f64::from(t.wrapping_sub(marks.start_ms)) / 1000.0
        });
    (speed, turned / span.max(1e-9), response)
}

/// The share of a coordinated turn's curvature, g tan(phi) / v^2, that `curvature` (1/m) is at
/// `bank_deg` and `speed` (m/s).
pub fn efficiency(curvature: f64, bank_deg: f64, speed: f64) -> f64 {
    curvature / (9.80665 * bank_deg.to_radians().tan() / (speed * speed))
}

/// The most the unit may fall behind its link in a chase, s of the aircraft's clock: a roll
/// response of the aircraft flown here. A unit further behind steers on states older than
/// its bank takes to answer, and the chase says more of the emulator than of the law.
pub const MAX_UNIT_LAG_S: f64 = 0.5;

/// An aircraft's chase `o` against the law's speed `v_pm` (m/s): the unit never more than
/// [`MAX_UNIT_LAG_S`] behind its link where that is measured; captured no later than the ideal
/// Dubins pursuer + 3 s, airspeed within 10 % of v_pm and height within a 10 m band through
/// it; the capture time.
pub fn chase_held(o: &Outcome, v_pm: f64) -> Result<f64, String> {
    if let Some(lag) = o.unit_lag.filter(|&lag| lag > MAX_UNIT_LAG_S) {
        return Err(format!(
            "the unit fell {lag:.2} s behind its link (more than {MAX_UNIT_LAG_S} s): \
             its emulator did not keep up with SITL"
        ));
    }
    let captured = o.captured.ok_or("never captured")?;
    let (lo, hi) = o.airspeed.ok_or("no airspeed during the chase")?;
    let held = captured <= o.ideal + 3.0
        && lo >= 0.9 * v_pm
        && hi <= 1.1 * v_pm
        && o.height.1 - o.height.0 <= 10.0;
    if held {
        Ok(captured)
    } else {
        Err(format!(
            "captured at {captured:.2} s (ideal {:.2} s); {}",
            o.ideal,
            super::energy_line(o, [v_pm, 0.0, 0.0, 0.0])
        ))
    }
}
