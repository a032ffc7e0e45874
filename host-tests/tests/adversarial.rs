//! Adversarial states and limits: each reaches its expected status with a finite command
//! within +-w_max, instantaneous and sampled.

use std::f32::consts::{PI, TAU};

use twocars::{evaluate_observation, Evaluation, Guidance, Law, Observation, Status, Variant};

const PAPER: [f32; 4] = [2.0, 2.0, 1.0, 1.0];

fn check(limits: [f32; 4], p: [f32; 3], e: [f32; 3], want: &[Status]) -> Evaluation<f32> {
    let observation = Observation {
        limits,
        pursuer: p,
        evader: e,
    };
    let ev = evaluate_observation::<f32>(&observation, Variant::Paper);
    assert!(
        want.contains(&ev.status),
        "{limits:?} {p:?} {e:?}: {:?}, want {want:?}",
        ev.status
    );
    let c = ev.command;
    assert!(c.pursuer.is_finite() && c.evader.is_finite(), "{c:?}");
    assert!(
        c.pursuer.abs() <= limits[1].abs() && c.evader.abs() <= limits[3].abs(),
        "{c:?}"
    );
    if let Some(r) = ev.report {
        for v in r.matrix.entries.iter().flatten().flatten() {
            assert!(v.is_finite(), "entry {v}");
        }
    }
    if let Ok(scene) = twocars::law::validate::<f32>(&observation) {
        let mut g = Guidance::new(Law::new(scene.limits, Variant::Paper), 0.01).unwrap();
        let s = g.step(&scene.pursuer, &scene.evader);
        assert_eq!(s.status, ev.status);
        assert!(s.command.pursuer.is_finite() && s.command.pursuer.abs() <= limits[1]);
        assert!(s.command.evader.is_finite() && s.command.evader.abs() <= limits[3]);
    }
    ev
}

fn upper(ev: &Evaluation<f32>) -> f32 {
    ev.report
        .and_then(|r| r.solution.upper)
        .unwrap_or(f32::INFINITY)
}

const PLAYED: &[Status] = &[Status::Ok, Status::NoValidTangent];

#[test]
fn coincident_vehicles_are_captured() {
    check(
        PAPER,
        [3.0, 4.0, 1.0],
        [3.0, 4.0, -2.0],
        &[Status::Captured],
    );
    check(PAPER, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], &[Status::Captured]);
}

#[test]
fn vehicles_on_each_others_turning_circles() {
    // Pursuer at the origin heading +x: its A circle is centred at (0, 0.5), radius 0.5.
    for angle in [0.0f32, 0.7, 1.6, 3.0, -2.0] {
        let e = [0.5 * angle.cos(), 0.5 + 0.5 * angle.sin(), angle + PI / 2.0];
        check(PAPER, [0.0, 0.0, 0.0], e, PLAYED);
    }
    // Evader at the origin heading +x: its C circle is centred at (0, -1), radius 1.
    for angle in [0.3f32, 2.0, -1.0] {
        let p = [angle.cos(), -1.0 + angle.sin(), angle - PI / 2.0];
        check(PAPER, p, [0.0, 0.0, 0.0], PLAYED);
    }
}

#[test]
fn circles_at_the_tangent_existence_limit_give_a_zero_length_tangent() {
    // A_p centred (0, 0.5); C_e of an evader at (0, 3) heading +x centred (0, 2): |D| = r_p + r_e.
    let ev = check(PAPER, [0.0, 0.0, 0.0], [0.0, 3.0, 0.0], PLAYED);
    let pair = ev.report.unwrap().pairs[0][1].expect("AC tangent exists at the limit");
    assert!(
        pair.tangent.length.abs() < 1e-3,
        "length {}",
        pair.tangent.length
    );
}

#[test]
fn headings_at_plus_and_minus_pi_agree() {
    let a = check(PAPER, [0.0, 0.0, PI], [-8.0, 3.0, -PI], PLAYED);
    let b = check(PAPER, [0.0, 0.0, -PI], [-8.0, 3.0, PI], PLAYED);
    assert!(
        (upper(&a) - upper(&b)).abs() < 1e-4 * upper(&a),
        "{} vs {}",
        upper(&a),
        upper(&b)
    );
}

#[test]
fn multiples_of_two_pi_inside_the_envelope_change_nothing_and_beyond_are_out_of_range() {
    let base = check(PAPER, [0.0, 0.0, 0.5], [-6.0, 4.0, 2.0], PLAYED);
    let turns = 1591.0 * TAU; // 9,996.5 rad, inside |theta| <= 1e4
    let wound = check(
        PAPER,
        [0.0, 0.0, 0.5 + turns],
        [-6.0, 4.0, 2.0 - turns],
        PLAYED,
    );
    // The wound heading carries f32 rounding of ~5e-4 rad; values move by r / v times that.
    assert!(
        (upper(&base) - upper(&wound)).abs() < 2e-3,
        "{} vs {}",
        upper(&base),
        upper(&wound)
    );
    check(
        PAPER,
        [0.0, 0.0, 1600.0 * TAU],
        [-6.0, 4.0, 2.0],
        &[Status::OutOfRange],
    );
    check(
        PAPER,
        [0.0, 0.0, 0.0],
        [-6.0, 4.0, -1.0e4 - 1.0],
        &[Status::OutOfRange],
    );
}

#[test]
fn limits_barely_satisfying_the_assumption_still_give_finite_values() {
    let v_pm = 1.0f32 + 1.0e-6; // 1.00000095 in f32
    let ev = check(
        [v_pm, 2.0, 1.0, 1.0],
        [0.0, 0.0, 0.0],
        [-20.0, 5.0, 1.0],
        PLAYED,
    );
    assert!(
        upper(&ev).is_finite() && upper(&ev) > 1.0e6,
        "{}",
        upper(&ev)
    );
    let w_pm = 1.0f32 + 1.0e-6;
    check(
        [2.0, w_pm, 1.0, 1.0],
        [0.0, 0.0, 0.0],
        [-20.0, 5.0, 1.0],
        PLAYED,
    );
    check(
        [1.0, 2.0, 1.0, 1.0],
        [0.0, 0.0, 0.0],
        [-20.0, 5.0, 1.0],
        &[Status::InvalidLimits],
    );
}

#[test]
fn subnormal_and_huge_coordinates() {
    let tiny = 1.0e-40f32;
    check(PAPER, [tiny, -tiny, tiny], [5.0, tiny, 0.0], PLAYED);
    check(
        PAPER,
        [0.0, 0.0, 0.0],
        [tiny, 0.0, 0.0],
        &[Status::Captured],
    );
    check(PAPER, [1.0e6, -1.0e6, 0.0], [-1.0e6, 1.0e6, 3.0], PLAYED);
    check(
        PAPER,
        [1.000_001e6, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        &[Status::OutOfRange],
    );
    check(
        PAPER,
        [f32::MAX, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        &[Status::OutOfRange],
    );
}

#[test]
fn subnormal_speeds_and_non_finite_fields_are_refused() {
    // Found by fuzzing: a subnormal evader speed made a capture time NaN before MIN_SPEED.
    let subnormal = 8.968_31e-44f32;
    check(
        [3.0, 2.144, subnormal, 2.0],
        [0.0, 3.0, 0.0],
        [3.0, 3.0, 3.0],
        &[Status::OutOfRange],
    );
    check(
        [2.0, 2.0, 1.0e-4, 1.0],
        [0.0, 0.0, 0.0],
        [5.0, 5.0, 0.0],
        &[Status::OutOfRange],
    );
    check(
        PAPER,
        [0.0, 0.0, f32::NAN],
        [5.0, 5.0, 0.0],
        &[Status::NonFiniteInput],
    );
    check(
        [2.0, f32::INFINITY, 1.0, 1.0],
        [0.0, 0.0, 0.0],
        [5.0, 5.0, 0.0],
        &[Status::NonFiniteInput],
    );
}
