//! `cargo xtask run --link mavlink --field` and its check in `cargo xtask test`: the MAVLink
//! image in QEMU chasing a target whose fixes come 200 ms late, 5 times a second, with GPS
//! noise of 0.2 r_p, through the unit's estimator (docs/field.md).
//!
//! The paper's four cases at ten times their scale (as `run --link mavlink`), the evader
//! playing the law on the exact states (the adversary suite's `law`). Each own state goes to
//! the unit at every period, exact; the target's fixes go as they arrive, stamped on the
//! autopilot's clock when they were taken. The unit is told the field: TC_TGT_LAG, TC_TGT_SIG,
//! TC_TGT_SIGH, and TC_CAPTURE 0.3 r_p. Each chase is set beside the same start on the host
//! with exact, instant states (`twocars_sim::field::chase`).

use twocars_sim::adversary::{Adversary, EvaderKind, Opponent};
use twocars_sim::autopilot::{Plane, HOME};
use twocars_sim::field::{chase, FieldModel, Fixes, Receiver};
use twocars_sim::scenarios::paper_cases;
use twocars_sim::sim::{
    advance, capture_within, distance, wrap_pi, SignFlips, SimParams, SimStatus,
};

use super::emulator;
use super::mavlink::{
    field, report, scaled_case, scaled_limits, set_params, set_scaled_limits, Peer, DT,
};
use crate::image::signing::SigningKey;
use crate::image::{self, Image};

/// The target fixes' lag (s), interval (s), position and heading noise (m at the scale, rad).
const LAG: f64 = 0.2;
const INTERVAL: f64 = 0.2;
const SIGMA_RADII: f64 = 0.2;
const HEADING_SIGMA: f64 = 0.1;
/// The guidance period, the pursuer's full turns: turns planned over 10 ms chase each fix's
/// noise.
const PERIOD_TURNS: f64 = 0.1;
/// The capture radius, r_p.
const CAPTURE_RADII: f64 = 0.3;
/// The most sign flips of the pursuer's setpoint a chase may have at the median.
const MEDIAN_FLIPS: u64 = 5;

/// One chase: capture time (s, infinite if never), the host's exact one, and sign flips.
struct Chase {
    t_capture: f64,
    exact: f64,
    flips: u64,
}

/// The field of these runs at `limits` (scaled), seeded by `seed`.
fn model(limits: [f64; 4], seed: u64) -> FieldModel {
    FieldModel {
        lag: LAG,
        fix_interval: INTERVAL,
        position_sigma: SIGMA_RADII / limits[1],
        heading_sigma: HEADING_SIGMA,
        seed,
        ..FieldModel::EXACT
    }
}

/// One period through the unit: the target's fixes that arrived (reports, oldest first) and
/// the own state's report; the unit's yaw-rate setpoint, rad/s (0 where it sent none). Fixes
/// that arrive together go all but the last alone, then the last with the own state.
fn step(peer: &mut Peer, targets: Vec<String>, own: &str) -> Result<f64, String> {
    let (last, earlier) = match targets.split_last() {
        Some((last, earlier)) => (last.as_str(), earlier),
        None => ("null", &[][..]),
    };
    for target in earlier {
        peer.ask(&format!(r#"{{"op": "target", "target": {target}}}"#))?;
    }
    let answer = peer.ask(&format!(
        r#"{{"op": "step", "own": {own}, "target": {last}}}"#
    ))?;
    Ok(field(&answer, "yaw_rate").unwrap_or(0.0))
}

/// The closed loop of one chase through the unit: the setpoints' yaw rates fly the pursuer.
fn fly(
    peer: &mut Peer,
    params: &SimParams,
    seed: u64,
    clock_ms: &mut u32,
) -> Result<Chase, String> {
    let limits = params.limits;
    let plane = Plane::new(HOME);
    let exact = chase(
        params,
        EvaderKind::Law,
        seed,
        &FieldModel::EXACT,
        Receiver::Raw,
    );
    let mut evader = Adversary::new(
        Opponent::Evader(EvaderKind::Law),
        limits,
        DT,
        params.eps,
        seed,
    )
    .ok_or("the evader's limits")?;
    let mut fixes = Fixes::new(model(limits, seed));
    let (mut p, mut e) = (params.pursuer, params.evader);
    let mut flips = SignFlips::default();
    let start_ms = *clock_ms;
    let on_clock = |t: f64| start_ms.wrapping_add((t * 1000.0).round() as i64 as u32);
    let steps = (params.t_max / DT).ceil() as u64;
    for k in 0..steps {
        let t0 = k as f64 * DT;
        let (w_e, v_e) = evader.command(t0, p, e);
        fixes.sample(t0, DT, e, v_e, w_e);
        let arrived: Vec<_> = fixes.arrived(t0).collect();
        let reports = arrived
            .iter()
            .map(|fix| report(&plane, on_clock(fix.taken), fix.state, limits[2]));
        let own = report(&plane, on_clock(t0), p, limits[0]);
        let w_p = step(peer, reports.collect(), &own)? / limits[0];
        flips.record(0, w_p, limits[1], false);
        let at = |tau: f64| (advance(p, limits[0], w_p, tau), advance(e, v_e, w_e, tau));
        let gap = |tau: f64| {
            let (a, b) = at(tau);
            distance(a, b)
        };
        let mut d_min = f64::INFINITY;
        if let Some(tau) = capture_within(DT, params.eps, gap, &mut d_min) {
            *clock_ms = on_clock(t0 + 1.0);
            return Ok(Chase {
                t_capture: t0 + tau,
                exact: exact.t_capture,
                flips: flips.count,
            });
        }
        let (np, ne) = at(DT);
        p = [np[0], np[1], wrap_pi(np[2])];
        e = [ne[0], ne[1], wrap_pi(ne[2])];
    }
    *clock_ms = on_clock(params.t_max + 1.0);
    Ok(Chase {
        t_capture: if exact.status == SimStatus::Captured {
            f64::INFINITY
        } else {
            f64::NAN
        },
        exact: exact.t_capture,
        flips: flips.count,
    })
}

/// The field's chases on `board`'s MAVLink image: whether every chase was captured and the
/// median of the sign flips is within [`MEDIAN_FLIPS`]; signed with `key` where given.
pub fn run_field(board: Image, key: Option<&SigningKey>) -> Result<bool, String> {
    let scaled = scaled_limits();
    let limits = scaled.map(f64::from);
    let r_p = 1.0 / limits[1];
    let turn = std::f32::consts::TAU / (scaled[0] * scaled[1]);
    let (elf, _) = image::build_checked(board, key)?;
    let launched = emulator::launch(&elf, board, false)?;
    let mut peer = Peer::start(launched.port, key)?;
    peer.ask(r#"{"op": "heartbeat"}"#)?;
    let sigma = model(limits, 0).position_sigma as f32;
    let mut ok = set_scaled_limits(&mut peer)?;
    ok &= set_params(
        &mut peer,
        &[
            ("TC_TGT_LAG", LAG as f32),
            ("TC_TGT_SIG", sigma),
            ("TC_TGT_SIGH", HEADING_SIGMA as f32),
            ("TC_CAPTURE", (CAPTURE_RADII * r_p) as f32),
            ("TC_PERIOD", PERIOD_TURNS as f32 * turn),
        ],
    )?;
    println!(
        "{}: target fixes {LAG} s late, every {INTERVAL} s, sigma {sigma} m ({SIGMA_RADII} r_p) \
         and {HEADING_SIGMA} rad; capture radius {} m",
        board.bin(),
        CAPTURE_RADII * r_p
    );
    // The autopilots' clocks well past 0: the target was tracked before each chase began.
    let mut clock_ms = 10_000;
    let mut flips = Vec::new();
    for (i, case) in paper_cases().into_iter().enumerate() {
        let params = scaled_case(&case, 40.0, CAPTURE_RADII * r_p);
        let c = fly(&mut peer, &params, 17 + i as u64, &mut clock_ms)?;
        let captured = c.t_capture.is_finite();
        ok &= captured;
        flips.push(c.flips);
        println!(
            "{}: {} at {:.3} s; exact, instant states on the host {:.3} s ({:+.1} %); {} sign flips",
            case.name,
            if captured { "captured" } else { "NOT CAPTURED" },
            c.t_capture,
            c.exact,
            100.0 * (c.t_capture - c.exact) / c.exact,
            c.flips
        );
        peer.ask(r#"{"op": "quiet", "seconds": 1.2}"#)?;
    }
    flips.sort_unstable();
    let median = flips.get(flips.len() / 2).copied().unwrap_or(u64::MAX);
    println!("sign flips: median {median} (at most {MEDIAN_FLIPS})");
    drop(peer);
    drop(launched);
    Ok(ok && median <= MEDIAN_FLIPS)
}
