//! The harness both autopilots' chases run in (`cargo xtask run --autopilot ardupilot|px4`): the
//! MAVLink router between the autopilot's SITL, the unit and the host; what the harness reads of
//! the link; one chase against a simulated evader, its fixes through the field; the unit as a
//! QEMU image or the companion binary; and what both autopilots' runs share: the starts, the
//! law's limits from the measured vehicle, the unit's parameters, the report of a chase.

pub mod aircraft;
pub mod backlog;
pub mod chase;
pub mod evader;
pub mod field;
pub mod harness;
pub mod message;
pub mod router;
pub mod script;
pub mod team;
pub mod unit;

use std::time::Duration;

use twocars_sim::adversary::EvaderKind;
use twocars_sim::sim::theorem_threshold;

use chase::{Outcome, Start};
use harness::{Harness, NoTarget, UNIT_COMPONENT};
use message::param_set;
use router::Source;

/// The rover's limits as driven: top speed at thrust 1, and the largest steady turn rate
/// either way at that speed.
#[derive(Clone, Copy, Debug)]
pub struct Measured {
    /// m/s.
    pub speed: f64,
    /// rad/s: the smaller of the two sides'.
    pub turn_rate: f64,
    /// speed / turn_rate, m.
    pub radius: f64,
    /// The yaw rate's response to a step of its setpoint: the time to 63 % of the rate it
    /// settles at, s.
    pub response: f64,
}

/// The share of the rover's largest turn rate the law may command: the rest is the rate
/// controller's room to track.
pub const TURN_MARGIN: f64 = 0.8;
/// Capture radius for rovers, m: a rover's length.
pub const CAPTURE_RADIUS: f64 = 1.0;
/// The target's system id (TC_TGT_SYSID's default).
pub const TARGET_SYSTEM: u8 = 2;

/// The law's limits for the measured rover: v_pm its top speed, w_pm the curvature of
/// [`TURN_MARGIN`] of its largest turn rate at that speed, the evader at half of each (the
/// paper's ratios).
pub fn law_limits(m: &Measured) -> [f64; 4] {
    let v_pm = (m.speed * 100.0).round() / 100.0;
    let w_pm = (TURN_MARGIN * m.turn_rate / m.speed * 100.0).floor() / 100.0;
    [v_pm, w_pm, v_pm / 2.0, w_pm / 2.0]
}

/// The law's limits for an aircraft flying `speed` (m/s, ground speed level) and `curvature`
/// (1/m, at the bank measured): v_pm the speed (to 0.1 m/s), w_pm [`TURN_MARGIN`] of the
/// curvature (three significant digits, rounded down), the evader at half of each.
pub fn aircraft_limits(speed: f64, curvature: f64) -> [f64; 4] {
    let v_pm = (speed * 10.0).round() / 10.0;
    let w = TURN_MARGIN * curvature;
    let scale = 10f64.powi(2 - w.log10().floor() as i32);
    let w_pm = (w * scale).floor() / scale;
    [v_pm, w_pm, v_pm / 2.0, w_pm / 2.0]
}

/// The airspeed and height an aircraft's chase held.
pub fn energy_line(o: &Outcome, limits: [f64; 4]) -> String {
    let (lo, hi) = o.airspeed.unwrap_or((f64::NAN, f64::NAN));
    format!(
        "energy: airspeed {lo:.2} to {hi:.2} m/s ({:+.1} % to {:+.1} % of TC_V_PM), height {:.1} to {:.1} m",
        100.0 * (lo / limits[0] - 1.0),
        100.0 * (hi / limits[0] - 1.0),
        o.height.0,
        o.height.1
    )
}

/// The starts: below the threshold (the paper's case 1 at the rover's scale) and beyond it (1.1
/// threshold ahead and to the right), each against the straight, the circling and the
/// law-playing evader; `short`: the first only.
pub fn starts(limits: [f64; 4], short: bool) -> Vec<Start> {
    starts_against(limits, short, &EVADERS[..3])
}

/// The evaders the chases fly against; the evader rover flies the zigzag too.
pub const EVADERS: [EvaderKind; 4] = [
    EvaderKind::Straight,
    EvaderKind::Circle {
        left: true,
        half: false,
    },
    EvaderKind::Law,
    EvaderKind::Zigzag,
];

/// [`starts`] against `evaders`.
pub fn starts_against(limits: [f64; 4], short: bool, evaders: &[EvaderKind]) -> Vec<Start> {
    // The paper's case 1 (the evader 6 m behind and 3 m to the right, same heading, with
    // r_p = 0.5 m), scaled by the law's r_p / 0.5 m.
    let scale = 2.0 / limits[1];
    let beyond = 1.1 * theorem_threshold(limits);
    let mut out = Vec::new();
    for &evader in evaders {
        out.push(Start {
            name: "below",
            ahead: -6.0 * scale,
            right: 3.0 * scale,
            heading: 0.0,
            evader,
        });
    }
    for &evader in evaders {
        out.push(Start {
            name: "beyond",
            ahead: beyond * 0.8,
            right: beyond * 0.6,
            heading: std::f64::consts::FRAC_PI_2,
            evader,
        });
    }
    if short {
        out.truncate(1);
    }
    out
}

/// Sets the unit's TC_* parameters (speeds first, so each step keeps the limits valid), its
/// capture radius `capture` (m) and guidance period `period` (s); Err where one is not echoed.
pub fn configure_unit(
    h: &mut Harness,
    limits: [f64; 4],
    capture: f64,
    period: f64,
) -> Result<(), String> {
    set_unit_params(
        h,
        &[
            ("TC_V_PM", limits[0]),
            ("TC_V_EM", limits[2]),
            ("TC_W_EM", limits[3]),
            ("TC_W_PM", limits[1]),
            ("TC_CAPTURE", capture),
            ("TC_PERIOD", period),
        ],
    )
}

/// Sets the unit's `values` in order; Err where one is not echoed.
pub fn set_unit_params(h: &mut Harness, values: &[(&str, f64)]) -> Result<(), String> {
    let unit = (1, UNIT_COMPONENT);
    for &(name, value) in values {
        let value = value as f32;
        let from = h.params.len();
        let message = param_set(unit, name, value);
        h.router.send_to_unit_as(router::GCS, &message)?;
        let echoed = |h: &Harness| {
            h.params[from..]
                .iter()
                .any(|(s, n, v)| *s == Source::Unit && n == name && *v == value)
        };
        if !h.pump_until(&mut NoTarget, Duration::from_secs(3), &mut |h| echoed(h))? {
            return Err(format!("the unit did not take {name} = {value}"));
        }
    }
    Ok(())
}

/// One chase in one paragraph.
pub fn report(o: &Outcome, limits: [f64; 4]) -> String {
    let captured = o.captured.map_or("NEVER CAPTURED".to_string(), |t| {
        format!(
            "captured at {t:.2} s, {:+.2} s against the ideal Dubins pursuer's {:.2} s",
            t - o.ideal,
            o.ideal
        )
    });
    format!(
        "{} vs {:?}: start {:.1} m; the law's value at t = 0 {:.2} s (the unit's first TC_T {}); {captured}\n  \
         causes: speed {:.2} m/s at 1 s, {:.1} m short of v_pm t by capture (~{:.2} s of delay at v_pm); \
         turn-rate tracking rms {:.2} rad/s ({:.2} away from the switches); {} setpoints, {} sign flips; {}\n  \
         failsafe: the unit's \"target stale\" {} after capture; from its last setpoint, the autopilot's word {} and its failsafe {} (a rover at a standstill, an aircraft at its own roll)",
        o.start.name,
        o.start.evader,
        o.distance,
        o.predicted,
        o.unit_predicted.map_or("none".to_string(), |v| format!("{v:.2} s")),
        o.speed_at_1s,
        o.speed_deficit,
        o.speed_deficit / limits[0],
        o.tracking_rms,
        o.tracking_rms_settled,
        o.setpoints,
        o.flips,
        lag_words(o),
        seconds(o.unit_stale_after),
        seconds(o.to_stop_message),
        seconds(o.to_failsafe),
    )
}

/// How far behind its link the unit fell in `o`, in words.
pub fn lag_words(o: &Outcome) -> String {
    o.unit_lag
        .map_or("the unit's lag unmeasured".to_string(), |s| {
            format!("the unit at most {s:.2} s behind its link")
        })
}

pub fn seconds(s: Option<f64>) -> String {
    s.map_or("never".to_string(), |s| format!("{s:.2} s"))
}
