//! Closed loop on the host: above the theorem's threshold the sampled law captures when it
//! predicted, and it does not chatter.

mod common;

use common::{paper_scene, scene, seeded_runner, Scene};
use host_tests::scenarios::{paper_cases, PAPER_LIMITS};
use host_tests::sim::{simulate, SimParams, SimResult, SimStatus};
use proptest::strategy::Strategy;
use twocars::Variant;

const DT: f64 = 0.001;
const EPS: f64 = 0.01;
/// "Within a few dt": the sampled command reaches each tangent within a period of the ideal.
const FEW_DT: f64 = 5.0 * DT;
/// Chattering bound: sign flips per run in the single digits.
const MAX_SIGN_FLIPS: u64 = 9;

/// Run parameters with time for the predicted capture and a margin.
fn params(s: &Scene, dt: f64) -> SimParams {
    let predicted = twocars::evaluate_observation::<f32>(&s.observation(), Variant::Paper)
        .report
        .and_then(|r| r.solution.upper)
        .map_or(100.0, f64::from);
    SimParams {
        limits: s.limits,
        pursuer: s.pursuer,
        evader: s.evader,
        dt,
        t_max: 1.2 * predicted.max(0.0) + 5.0,
        eps: EPS,
    }
}

fn threshold(limits: [f64; 4]) -> f64 {
    let [v_pm, _, v_em, w_em] = limits;
    let r_e = 1.0 / w_em;
    2.0 * r_e + 2.0 * std::f64::consts::PI * r_e * v_pm / v_em
}

fn above_threshold(s: &Scene) -> bool {
    let d0 = (s.pursuer[0] - s.evader[0]).hypot(s.pursuer[1] - s.evader[1]);
    d0 >= threshold(s.limits)
}

/// Capture time to eps, plus the time the pursuer needs to close the last eps (at v_pm - v_em on
/// a common line), compared with the prediction at t = 0.
fn check_capture_matches_prediction(r: &SimResult, limits: [f64; 4]) {
    assert_eq!(r.status, SimStatus::Captured, "{r:?}");
    let closed = r.t_capture + EPS / (limits[0] - limits[2]);
    let saddle = (r.predicted - r.predicted_lower).abs() <= 1e-4 * r.predicted.abs();
    if saddle {
        assert!(
            (closed - r.predicted).abs() <= FEW_DT,
            "captured {closed} vs predicted {}",
            r.predicted
        );
    } else {
        assert!(
            closed >= r.predicted_lower - FEW_DT && closed <= r.predicted + FEW_DT,
            "captured {closed} outside [{}, {}]",
            r.predicted_lower,
            r.predicted
        );
    }
}

#[test]
fn above_the_threshold_at_the_paper_limits_capture_matches_the_prediction() {
    let far = paper_scene(40.0).prop_filter("above threshold", above_threshold);
    seeded_runner(64)
        .run(&far, |s| {
            let r = simulate::<f32>(&params(&s, DT), Variant::Paper, false);
            check_capture_matches_prediction(&r, s.limits);
            assert!(
                r.sign_flips <= MAX_SIGN_FLIPS,
                "{} sign flips",
                r.sign_flips
            );
            Ok(())
        })
        .unwrap();
}

/// At random limits the capture time matches too. Sign flips are printed, not bounded: slow
/// closing chases (v_pm / v_em near 1.1, captures after 10^2 to 10^3 s) dither in their last
/// seconds (see the closing note of issue 4).
#[test]
fn above_the_threshold_at_random_limits_capture_matches_the_prediction() {
    let far = scene(60.0).prop_filter("above threshold", above_threshold);
    let flips = std::cell::RefCell::new(Vec::new());
    seeded_runner(64)
        .run(&far, |s| {
            let r = simulate::<f32>(&params(&s, DT), Variant::Paper, false);
            check_capture_matches_prediction(&r, s.limits);
            flips.borrow_mut().push(r.sign_flips);
            Ok(())
        })
        .unwrap();
    let mut flips = flips.into_inner();
    flips.sort_unstable();
    let at = |q: f64| {
        flips
            .get(((flips.len() - 1) as f64 * q) as usize)
            .copied()
            .unwrap_or(0)
    };
    println!(
        "random limits, {} runs: sign flips median {}, 90th percentile {}, max {}",
        flips.len(),
        at(0.5),
        at(0.9),
        at(1.0)
    );
}

#[test]
fn the_paper_cases_capture_as_predicted_without_chattering() {
    for dt in [0.001, 0.01] {
        for case in paper_cases() {
            let s = Scene {
                limits: PAPER_LIMITS,
                pursuer: case.pursuer,
                evader: case.evader,
            };
            let r = simulate::<f32>(&params(&s, dt), Variant::Paper, false);
            assert_eq!(r.status, SimStatus::Captured, "{}", case.name);
            let closed = r.t_capture + EPS / (PAPER_LIMITS[0] - PAPER_LIMITS[2]);
            assert!(
                closed >= r.predicted_lower - 5.0 * dt && closed <= r.predicted + 5.0 * dt,
                "{} dt {dt}: {closed} vs [{}, {}]",
                case.name,
                r.predicted_lower,
                r.predicted
            );
            assert!(
                r.sign_flips <= MAX_SIGN_FLIPS,
                "{} dt {dt}: {} flips",
                case.name,
                r.sign_flips
            );
            assert!(
                r.switches <= MAX_SIGN_FLIPS,
                "{} dt {dt}: {} switches",
                case.name,
                r.switches
            );
        }
    }
}

#[test]
fn invalid_parameters_and_initial_statuses_are_reported() {
    let s = Scene {
        limits: PAPER_LIMITS,
        pursuer: [0.0, 0.0, 0.0],
        evader: [5.0, 5.0, 0.0],
    };
    for (dt, t_max, eps) in [
        (0.0, 30.0, 0.01),
        (0.01, f64::NAN, 0.01),
        (0.01, 30.0, -1.0),
        (1e-7, 10.0, 0.01),
    ] {
        let r = simulate::<f32>(
            &SimParams {
                dt,
                t_max,
                eps,
                ..params(&s, 0.01)
            },
            Variant::Paper,
            false,
        );
        assert_eq!(r.status, SimStatus::InvalidSimParams, "{dt} {t_max} {eps}");
    }
    let bad = Scene {
        limits: [1.0, 2.0, 2.0, 1.0],
        ..s
    };
    let r = simulate::<f32>(&params(&bad, 0.01), Variant::Paper, false);
    assert_eq!(r.status.name(), "invalid_limits");
    let far = Scene {
        evader: [40.0, 0.0, 0.0],
        ..s
    };
    let r = simulate::<f32>(
        &SimParams {
            t_max: 0.5,
            ..params(&far, 0.01)
        },
        Variant::Paper,
        false,
    );
    assert_eq!(r.status, SimStatus::Timeout);
    assert!(r.t_capture.is_infinite());
}

#[test]
fn exact_motion_closes_a_full_circle() {
    let start = [1.0, 2.0, 0.3];
    let (v, w) = (2.0, 0.5);
    let period = std::f64::consts::TAU / (v * w);
    let end = host_tests::sim::advance(start, v, w, period);
    assert!((end[0] - start[0]).abs() < 1e-12 && (end[1] - start[1]).abs() < 1e-12);
    let half = host_tests::sim::advance(start, v, w, period / 2.0);
    let diameter = (half[0] - start[0]).hypot(half[1] - start[1]);
    assert!((diameter - 2.0 / w).abs() < 1e-12, "diameter {diameter}");
}
