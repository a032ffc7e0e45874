//! Every status of the contract, reached from a concrete input, with its safe command.

use twocars::law::{evaluate_observation, Observation};
use twocars::{Evaluation, Status, Variant};

const PI: f32 = core::f32::consts::PI;

fn eval(limits: [f32; 4], pursuer: [f32; 3], evader: [f32; 3]) -> Evaluation<f32> {
    evaluate_observation::<f32>(
        &Observation {
            limits,
            pursuer,
            evader,
        },
        Variant::Paper,
    )
}

const PAPER: [f32; 4] = [2.0, 2.0, 1.0, 1.0];

fn assert_straight(e: &Evaluation<f32>) {
    assert_eq!(
        (e.command.pursuer, e.command.evader),
        (0.0, 0.0),
        "{:?}",
        e.status
    );
    assert!(e.report.is_none());
}

#[test]
fn ok_gives_the_law_command_at_full_curvature() {
    let e = eval(PAPER, [0.0, 0.0, PI / 2.0], [-3.0, -6.0, PI / 2.0]);
    assert_eq!(e.status, Status::Ok);
    assert_eq!(e.command.pursuer.abs(), 2.0);
    assert_eq!(e.command.evader.abs(), 1.0);
}

#[test]
fn nan_or_infinity_anywhere_is_non_finite_input() {
    for i in 0..10 {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let mut f = [2.0, 2.0, 1.0, 1.0, 0.0, 0.0, 0.0, 5.0, 5.0, 0.0];
            f[i] = bad;
            let e = eval(
                [f[0], f[1], f[2], f[3]],
                [f[4], f[5], f[6]],
                [f[7], f[8], f[9]],
            );
            assert_eq!(e.status, Status::NonFiniteInput, "field {i} = {bad}");
            assert_straight(&e);
        }
    }
}

#[test]
fn limits_violating_assumption_one_are_invalid_limits() {
    for limits in [
        [1.0, 2.0, 2.0, 1.0], // slower pursuer
        [1.0, 2.0, 1.0, 1.0], // equal speeds
        [2.0, 1.0, 1.0, 1.0], // equal curvatures
        [2.0, 1.0, 1.0, 2.0], // less agile pursuer
        [2.0, 2.0, 0.0, 1.0], // evader speed zero
        [2.0, 2.0, 1.0, 0.0], // evader curvature zero (infinite radius)
        [2.0, 2.0, -1.0, 1.0],
        [-1.0, -2.0, -3.0, -4.0],
    ] {
        let e = eval(limits, [0.0, 0.0, 0.0], [5.0, 5.0, 0.0]);
        assert_eq!(e.status, Status::InvalidLimits, "{limits:?}");
        assert_straight(&e);
    }
}

#[test]
fn states_or_limits_outside_the_f32_envelope_are_out_of_range() {
    let cases = [
        (PAPER, [1.5e6, 0.0, 0.0], [0.0, 0.0, 0.0]),
        (PAPER, [0.0, 0.0, 0.0], [0.0, -1.0e7, 0.0]),
        (PAPER, [0.0, 0.0, 2.0e4], [5.0, 0.0, 0.0]),
        (PAPER, [0.0, 0.0, 0.0], [5.0, 0.0, -1.0e5]),
        ([2.0, 2.0, 1.0, 1.0e-7], [0.0, 0.0, 0.0], [5.0, 0.0, 0.0]), // radius 1e7 m
        ([f32::MAX, 2.0, 1.0, 1.0], [0.0, 0.0, 0.0], [5.0, 0.0, 0.0]),
    ];
    for (limits, p, e) in cases {
        let ev = eval(limits, p, e);
        assert_eq!(ev.status, Status::OutOfRange, "{limits:?} {p:?} {e:?}");
        assert_straight(&ev);
    }
}

#[test]
fn headings_at_the_envelope_edge_still_evaluate() {
    let e = eval(PAPER, [0.0, 0.0, 1.0e4], [5.0, 5.0, -1.0e4]);
    assert_eq!(e.status, Status::Ok);
}

#[test]
fn coincident_positions_are_captured_whatever_the_headings() {
    for theta in [0.0, 1.0, -3.0] {
        let e = eval(PAPER, [1.0, 1.0, 0.0], [1.0, 1.0 + 4.0e-7, theta]);
        assert_eq!(e.status, Status::Captured);
        assert_straight(&e);
    }
    // Just outside 1e-6 r_p (r_p = 0.5 m) the game is played.
    let e = eval(PAPER, [0.0, 0.0, 0.0], [0.0, 1.0e-5, 0.0]);
    assert_ne!(e.status, Status::Captured);
}

#[test]
fn overlapping_circles_without_a_finite_row_give_no_valid_tangent_and_the_fallback() {
    // Found by a scan of states within 2 m: both pursuer rows contain a pair whose circles
    // overlap (no valid tangent), so the upper value is infinite.
    let e = eval(PAPER, [0.0, 0.0, 0.0], [-1.1336, -0.3115, -2.9591]);
    assert_eq!(e.status, Status::NoValidTangent);
    let r = e.report.expect("matrix reported");
    assert!(r.solution.upper.is_none());
    assert!(r
        .matrix()
        .entries
        .iter()
        .all(|row| row.iter().any(Option::is_none)));
    // Fallback: the evader is behind-left of the pursuer (bearing ~ -164 deg, so turn clockwise);
    // the evader turns away from the pursuer at its full curvature.
    assert_eq!(e.command.pursuer, -2.0);
    assert!(e.command.evader.abs() == 1.0);
    let bearing_away = (-0.3115f32).atan2(-1.1336) - (-2.9591);
    assert_eq!(e.command.evader.signum(), bearing_away.sin().signum());
}
