//! Closed loop on the host: above the theorem's threshold the sampled law captures when it
//! predicted, and it does not chatter.

mod common;

use common::{paper_scene, scene, seeded_runner, Scene};
use proptest::strategy::Strategy;
use std::f64::consts::PI;
use twocars::{Policy, Variant};
use twocars_sim::scenarios::EPS;
use twocars_sim::scenarios::{paper_cases, PAPER_LIMITS};
use twocars_sim::sim::{simulate, theorem_threshold, SimParams, SimResult, SimStatus};
use twocars_sim::stats::quantile;

const DT: f64 = 0.001;
/// "Within a few dt": the sampled command reaches each tangent within a period of the ideal.
const FEW_DT: f64 = 5.0 * DT;
/// Chattering bound: sign flips per run in the single digits.
const MAX_SIGN_FLIPS: u64 = 9;

/// Run parameters with time for the predicted capture and a margin.
fn params(s: &Scene, dt: f64) -> SimParams {
    let predicted = twocars::law::evaluate_observation::<f32>(&s.observation(), Variant::Paper)
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

fn above_threshold(s: &Scene) -> bool {
    let d0 = (s.pursuer[0] - s.evader[0]).hypot(s.pursuer[1] - s.evader[1]);
    d0 >= theorem_threshold(s.limits)
}

/// Capture time to eps, plus the time the pursuer needs to close the last eps (at v_pm - v_em on
/// a common line), compared with the prediction at t = 0. Each player may choose an option
/// within the tie band (1e-4 relative, the f32 law's) of its value, so a capture along a tied
/// row or column may come that much after upper (before lower): a tail chase predicted at 155 s
/// may end 15 ms late. A capture later than that passes only if the pursuer had come within
/// eps plus five periods' travel of the evader by then (the run's trajectory, `r` recorded):
/// the law brought it there on time and the sampled command lost the last centimetres, where a
/// heading error of the tangent grows as the distance shrinks (`TWOCARS_SEED=75`: 2.8 cm apart
/// 10 ms before the predicted 26.528 s, the A circle's arc read 2 pi - 0.039 rad, one period's
/// turn being 0.036 rad, and the pursuer turned a full circle: captured at 26.888 s;
/// docs/closed-loop.md). Returns whether it did.
fn check_capture_matches_prediction(r: &SimResult, limits: [f64; 4]) -> bool {
    assert_eq!(r.status, SimStatus::Captured, "{r:?}");
    let band = f64::from(<f32 as twocars::Scalar>::TIE_BAND);
    let closed = r.point_capture(limits, EPS);
    let saddle = (r.predicted - r.predicted_lower).abs() <= band * r.predicted.abs();
    let (low, high) = (
        r.predicted_lower - FEW_DT - band * r.predicted_lower.abs(),
        r.predicted + FEW_DT + band * r.predicted.abs(),
    );
    let early = if saddle {
        r.predicted - FEW_DT - band * r.predicted.abs()
    } else {
        low
    };
    assert!(
        closed >= early,
        "captured {closed}, before [{}, {}]",
        r.predicted_lower,
        r.predicted
    );
    if closed <= high {
        return false;
    }
    let reach = EPS + limits[0] * FEW_DT;
    let nearest = r
        .trajectory
        .iter()
        .filter(|(t, _, _)| *t <= high)
        .map(|(_, p, e)| (p[0] - e[0]).hypot(p[1] - e[1]))
        .fold(f64::INFINITY, f64::min);
    assert!(
        nearest <= reach,
        "captured {closed} after [{}, {}], {nearest} m apart by then",
        r.predicted_lower,
        r.predicted
    );
    true
}

#[test]
fn above_the_threshold_at_the_paper_limits_capture_matches_the_prediction() {
    let far = paper_scene(40.0).prop_filter("above threshold", above_threshold);
    let lost_last_centimetres = std::cell::Cell::new(0);
    seeded_runner(64)
        .run(&far, |s| {
            let r = simulate::<f32>(&params(&s, DT), Variant::Paper, Policy::Paper, true);
            let lost = check_capture_matches_prediction(&r, s.limits);
            lost_last_centimetres.set(lost_last_centimetres.get() + usize::from(lost));
            assert!(
                r.sign_flips <= MAX_SIGN_FLIPS,
                "{} sign flips",
                r.sign_flips
            );
            Ok(())
        })
        .unwrap();
    println!(
        "paper limits, 64 runs: {} on time only to within eps plus 5 dt (the last centimetres lost)",
        lost_last_centimetres.get()
    );
}

fn quantiles(mut values: Vec<u64>) -> (u64, u64, u64) {
    values.sort_unstable();
    let at = |q: f64| quantile(&values, q).unwrap_or(0);
    (at(0.5), at(0.9), at(1.0))
}

/// At random limits the capture time matches too, and the command does not chatter over the
/// whole run, the last centimetres included (the simulator hands the law a frame centred on the
/// pursuer; with f32 absolute positions long chases dithered at the end, docs/closed-loop.md).
#[test]
fn above_the_threshold_at_random_limits_capture_matches_the_prediction() {
    let far = scene(60.0).prop_filter("above threshold", above_threshold);
    let flips = std::cell::RefCell::new(Vec::new());
    let lost_last_centimetres = std::cell::Cell::new(0);
    seeded_runner(64)
        .run(&far, |s| {
            let r = simulate::<f32>(&params(&s, DT), Variant::Paper, Policy::Paper, true);
            let lost = check_capture_matches_prediction(&r, s.limits);
            lost_last_centimetres.set(lost_last_centimetres.get() + usize::from(lost));
            assert!(
                r.sign_flips <= MAX_SIGN_FLIPS,
                "{} sign flips ({} in the near field)",
                r.sign_flips,
                r.near_field_sign_flips
            );
            flips.borrow_mut().push(r.sign_flips);
            Ok(())
        })
        .unwrap();
    let flips = flips.into_inner();
    let (median, p90, max) = quantiles(flips.clone());
    println!(
        "random limits, {} runs: sign flips per run median {median}, 90th percentile {p90}, max {max}; \
         {} on time only to within eps plus 5 dt (the last centimetres lost)",
        flips.len(),
        lost_last_centimetres.get()
    );
}

/// Above the threshold the near-field policy is the paper's law until the law's own prediction
/// breaks: wherever the paper's law captured as predicted, the near-field policy captures no later
/// (dt = 10 ms, where the last centimetres are decided to the millimetre).
#[test]
fn the_near_field_policy_does_not_lengthen_runs_the_paper_law_predicted() {
    let far = scene(60.0).prop_filter("above threshold", above_threshold);
    seeded_runner(48)
        .run(&far, |s| {
            let p = params(&s, 0.01);
            let paper = simulate::<f32>(&p, Variant::Paper, Policy::Paper, false);
            let ours = simulate::<f32>(&p, Variant::Paper, Policy::Flight, false);
            let closed = paper.point_capture(s.limits, EPS);
            let held = paper.status == SimStatus::Captured
                && (closed - paper.predicted).abs() <= 5.0 * p.dt;
            if held {
                assert!(
                    ours.t_capture <= paper.t_capture + 5.0 * p.dt,
                    "near-field {} vs paper {}",
                    ours.t_capture,
                    paper.t_capture
                );
            }
            Ok(())
        })
        .unwrap();
}

/// Below the threshold, at the paper's limits and initial distances 2 to 6.5 m, the near-field
/// policy shortens the mean capture time and the worst lateness past the law's own prediction,
/// and chatters less than the paper's law. (It does lengthen some runs: `cargo xtask report`.)
#[test]
fn below_the_threshold_the_near_field_policy_shortens_the_worst_capture() {
    let near = (2.0f64..6.5, -PI..PI, -PI..PI, -PI..PI);
    let runs = std::cell::RefCell::new(Vec::new());
    seeded_runner(200)
        .run(&near, |(d0, bearing, theta_p, theta_e)| {
            let p = SimParams {
                limits: PAPER_LIMITS,
                pursuer: [0.0, 0.0, theta_p],
                evader: [d0 * bearing.cos(), d0 * bearing.sin(), theta_e],
                dt: 0.01,
                t_max: 30.0,
                eps: EPS,
            };
            let paper = simulate::<f32>(&p, Variant::Paper, Policy::Paper, false);
            let ours = simulate::<f32>(&p, Variant::Paper, Policy::Flight, false);
            assert_eq!(ours.status, SimStatus::Captured, "{p:?}");
            runs.borrow_mut().push((paper, ours));
            Ok(())
        })
        .unwrap();
    let runs = runs.into_inner();
    // Worst lateness: capture time past the law's own prediction at t = 0.
    let late = |r: &SimResult| r.t_capture - r.predicted;
    let worst = |pick: fn(&(SimResult, SimResult)) -> &SimResult| {
        runs.iter().map(|r| late(pick(r))).fold(f64::MIN, f64::max)
    };
    let mean = |pick: fn(&(SimResult, SimResult)) -> &SimResult| {
        runs.iter().map(|r| pick(r).t_capture).sum::<f64>() / runs.len() as f64
    };
    let (paper_late, ours_late) = (worst(|r| &r.0), worst(|r| &r.1));
    let (paper_mean, ours_mean) = (mean(|r| &r.0), mean(|r| &r.1));
    let (_, _, ours_flips) = quantiles(runs.iter().map(|r| r.1.sign_flips).collect());
    let (_, _, paper_flips) = quantiles(runs.iter().map(|r| r.0.sign_flips).collect());
    println!(
        "near field, {} runs: mean capture paper {paper_mean:.3} s, near-field {ours_mean:.3} s; \
         worst lateness past the prediction paper {paper_late:.3} s, near-field {ours_late:.3} s; \
         max sign flips paper {paper_flips}, near-field {ours_flips}",
        runs.len()
    );
    assert!(ours_late < paper_late);
    assert!(ours_mean < paper_mean);
    assert!(
        ours_flips < paper_flips,
        "{ours_flips} vs {paper_flips} sign flips"
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
            let r = simulate::<f32>(&params(&s, dt), Variant::Paper, Policy::Paper, false);
            assert_eq!(r.status, SimStatus::Captured, "{}", case.name);
            let closed = r.point_capture(PAPER_LIMITS, EPS);
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
            Policy::Paper,
            false,
        );
        assert_eq!(r.status, SimStatus::InvalidSimParams, "{dt} {t_max} {eps}");
    }
    let bad = Scene {
        limits: [1.0, 2.0, 2.0, 1.0],
        ..s
    };
    let r = simulate::<f32>(&params(&bad, 0.01), Variant::Paper, Policy::Paper, false);
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
        Policy::Paper,
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
    let end = twocars_sim::sim::advance(start, v, w, period);
    assert!((end[0] - start[0]).abs() < 1e-12 && (end[1] - start[1]).abs() < 1e-12);
    let half = twocars_sim::sim::advance(start, v, w, period / 2.0);
    let diameter = (half[0] - start[0]).hypot(half[1] - start[1]);
    assert!((diameter - 2.0 / w).abs() < 1e-12, "diameter {diameter}");
}
