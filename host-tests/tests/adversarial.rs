//! Adversarial states and limits: each reaches its expected status with a finite command
//! within +-w_max, instantaneous and sampled.

use std::f32::consts::{PI, TAU};

use twocars::law::{evaluate_observation, Observation};
use twocars::{Evaluation, Guidance, Law, Status, Variant};

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
        for v in r.matrix().entries.iter().flatten().flatten() {
            assert!(v.is_finite(), "entry {v}");
        }
    }
    if let Ok(scene) = twocars::law::validate::<f32>(&observation) {
        let mut g = Guidance::new(
            Law::new(scene.limits, Variant::Paper),
            0.01,
            twocars::Policy::Paper,
        )
        .unwrap();
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

/// The fixed-point backend's envelope: inside it the law plays; outside it `out_of_range` with
/// the safe command, never a wrapped or saturated value.
#[test]
fn fixed_point_reports_inputs_outside_its_envelope() {
    use twocars::num::fixed::Fixed;
    let fixed = |limits: [f32; 4], p: [f32; 3], e: [f32; 3]| {
        let observation = Observation {
            limits,
            pursuer: p,
            evader: e,
        };
        let ev = evaluate_observation::<Fixed>(&observation, Variant::Paper);
        let units = ev.units;
        let (wp, we) = (
            units.curvature(ev.command.pursuer),
            units.curvature(ev.command.evader),
        );
        assert!(wp.is_finite() && wp.abs() <= f64::from(limits[1]) * (1.0 + 1e-6));
        assert!(we.is_finite() && we.abs() <= f64::from(limits[3]) * (1.0 + 1e-6));
        if !PLAYED.contains(&ev.status) {
            assert_eq!((wp, we), (0.0, 0.0), "{:?}", ev.status);
        }
        ev.status
    };
    let origin = [1.0e5, -1.0e5, 0.3];
    let at = |dx: f32, dy: f32| [origin[0] + dx, origin[1] + dy, -1.0];
    // r_p = 0.5 m: 200 r_p = 100 m on each axis, wherever the pursuer is.
    assert_eq!(fixed(PAPER, origin, at(99.0, -99.0)), Status::Ok);
    assert_eq!(fixed(PAPER, origin, at(101.0, 0.0)), Status::OutOfRange);
    assert_eq!(fixed(PAPER, origin, at(0.0, -101.0)), Status::OutOfRange);
    // A fixed-wing scale: r_p = 150 m, 20 km apart.
    let wing = [25.0, 1.0 / 150.0, 15.0, 1.0 / 400.0];
    assert_eq!(
        fixed(wing, [0.0, 0.0, 0.0], [2.0e4, 1.5e4, 2.0]),
        Status::Ok
    );
    // Ratios: r_e / r_p <= 16, 1/16 <= v_em / v_pm <= 15/16.
    assert_eq!(
        fixed([2.0, 2.0, 1.0, 0.1], origin, at(5.0, 5.0)),
        Status::OutOfRange
    );
    assert!(PLAYED.contains(&fixed([2.0, 2.0, 1.0, 0.2], origin, at(5.0, 5.0))));
    let barely = [1.0 + 1e-6, 2.0, 1.0, 1.0];
    assert_eq!(fixed(barely, origin, at(5.0, 5.0)), Status::OutOfRange);
    assert_eq!(
        fixed([20.0, 2.0, 1.0, 1.0], origin, at(5.0, 5.0)),
        Status::OutOfRange
    );
    // Any heading: multiples of 2 pi inside the f32 envelope play as their reduced angle.
    let turns = 1000.0 * TAU;
    let reduced = fixed(PAPER, [0.0, 0.0, 0.3], [3.0, 4.0, -1.0]);
    assert_eq!(reduced, Status::Ok);
    assert_eq!(
        fixed(PAPER, [0.0, 0.0, 0.3 + turns], [3.0, 4.0, -1.0 - turns]),
        Status::Ok
    );
    assert_eq!(
        fixed(PAPER, [0.0, 0.0, 2.0e4], [3.0, 4.0, 0.0]),
        Status::OutOfRange
    );
    // Coincident vehicles, on each other's circles, heading +-pi.
    assert_eq!(fixed(PAPER, origin, origin), Status::Captured);
    // Apart by more than the capture radius (1e-6 r_p = 5e-7 m) but by less than half a raw
    // unit on each axis (2^-15 r_p = 1.5e-5 m): the positions would round to one point and read
    // as captured; the backend cannot play them. Within the capture radius they are captured,
    // and from one raw unit apart they are played.
    let still = [0.0, 0.0, 0.3];
    let near = |dx: f32, dy: f32| [dx, dy, -1.0];
    assert_eq!(fixed(PAPER, still, near(1.0e-5, 0.0)), Status::OutOfRange);
    assert_eq!(
        fixed(PAPER, still, near(-6.0e-6, 6.0e-6)),
        Status::OutOfRange
    );
    assert_eq!(fixed(PAPER, still, near(3.0e-7, -3.0e-7)), Status::Captured);
    let one_unit = fixed(PAPER, still, near(0.0, 3.1e-5));
    assert!(PLAYED.contains(&one_unit), "{one_unit:?}");
    assert!(PLAYED.contains(&fixed(PAPER, [0.0, 0.0, PI], [0.0, 1.0, -PI])));
}

/// The fixed-point backend's `+`, `-` and `*` are unchecked in release builds: its envelope must
/// keep every intermediate of the law in range. This test (a debug build: an overflow panics)
/// plays the law and both sampled policies, two periods each, at the corners of the envelope:
/// r_e / r_p = 16, v_em / v_pm = 1/16 and 15/16, the evader up to 200 r_p away on each axis
/// (and up to 0.1 r_p),
/// headings all round, and the shortest and longest control periods `Guidance::new` accepts.
#[test]
fn fixed_point_law_stays_in_range_at_the_corners_of_its_envelope() {
    use twocars::num::fixed::Fixed;
    use twocars::{Limits, Policy};
    // r_p = 1 cm at 100 m/s: the law's time unit is 1e-4 s, so a period of up to 1e3 s reaches
    // the longest the backend accepts.
    let (v_pm, w_pm, r_p) = (100.0_f32, 100.0_f32, 0.01_f32);
    let origin = [10.0_f32, -10.0];
    let (mut played, mut periods) = (0, 0);
    for v_em in [v_pm / 16.0, v_pm / 2.0, v_pm * 15.0 / 16.0] {
        let limits = Limits::<Fixed>::new(v_pm, w_pm, v_em, w_pm / 16.0).expect("in the envelope");
        let accepted = |dt: f32| {
            Guidance::new(Law::new(limits, Variant::Paper), dt, twocars::Policy::Paper).is_ok()
        };
        // The accepted periods form one interval: its ends by bisection on a log scale, from an
        // accepted period toward a refused one.
        let end = |mut inside: f32, mut outside: f32| {
            for _ in 0..60 {
                let mid = (inside * outside).sqrt();
                if accepted(mid) {
                    inside = mid
                } else {
                    outside = mid
                }
            }
            inside
        };
        let middle = 1.0e-2_f32;
        assert!(accepted(middle) && !accepted(1.0e-9));
        let short = end(middle, 1.0e-9);
        let long = if accepted(1.0e3) {
            1.0e3
        } else {
            end(middle, 1.0e3)
        };
        for dt in [short, middle, long] {
            let guidance =
                Guidance::new(Law::new(limits, Variant::Paper), dt, twocars::Policy::Paper)
                    .expect("accepted");
            periods += 1;
            // Offsets up to 200 r_p, and up to 0.1 r_p, where the near field's homing divides
            // by the distance.
            for (scale, i, j) in [100.0, 0.05]
                .iter()
                .flat_map(|&s| (0..25).map(move |k| (s, k / 5, k % 5)))
            {
                let offset = |n: i32| scale * r_p * (n - 2) as f32;
                for (a, b) in (0..256).map(|k| (k / 16, k % 16)) {
                    let heading = |n: i32| -PI + TAU * n as f32 / 16.0;
                    let p = [origin[0], origin[1], heading(a)];
                    let e = [origin[0] + offset(i), origin[1] + offset(j), heading(b)];
                    let (p, e) = limits.states(p, e).expect("in the envelope");
                    for policy in [Policy::Paper, Policy::Flight] {
                        let mut g = guidance.with_policy(policy);
                        for _ in 0..2 {
                            let d = g.decide(&p, &e);
                            let w = d.units.curvature(d.command.pursuer);
                            assert!(w.is_finite() && w.abs() <= f64::from(w_pm) * 1.000_001);
                            if PLAYED.contains(&d.status) {
                                played += 1;
                            } else {
                                assert_eq!(d.status, Status::Captured);
                            }
                        }
                    }
                }
            }
        }
    }
    println!("{periods} periods, {played} decisions played");
    assert!(periods == 9 && played > 100_000, "{periods} {played}");
}

/// Every period, accepted or refused, is judged without leaving the fixed-point range: a period
/// near the longest accepted with v_em / v_pm = 0.7 made the check dt + tie floor overflow
/// (found by fuzzing). The accepted periods form one interval.
#[test]
fn fixed_point_guidance_judges_every_period_within_its_range() {
    use twocars::num::fixed::Fixed;
    use twocars::Limits;
    let (mut accepted_total, mut refused_total) = (0, 0);
    for sixteenths in 1..=15 {
        let v_em = 100.0 * sixteenths as f32 / 16.0;
        let limits = Limits::<Fixed>::new(100.0, 100.0, v_em, 100.0 / 16.0).expect("envelope");
        // dt from 1e-9 s to 1e3 s in 1,200 steps of 10^(1/100); the law's time unit is 1e-4 s.
        let verdicts: Vec<bool> = (0..=1200)
            .map(|k| 10f32.powf(-9.0 + k as f32 / 100.0))
            .map(|dt| {
                Guidance::new(Law::new(limits, Variant::Paper), dt, twocars::Policy::Paper).is_ok()
            })
            .collect();
        let first = verdicts
            .iter()
            .position(|&ok| ok)
            .expect("some period accepted");
        let last = verdicts
            .iter()
            .rposition(|&ok| ok)
            .expect("some period accepted");
        assert!(
            verdicts[first..=last].iter().all(|&ok| ok),
            "{sixteenths}/16: a gap"
        );
        assert!(
            first > 0 && last < 1200,
            "{sixteenths}/16: {first}..={last}"
        );
        accepted_total += last + 1 - first;
        refused_total += verdicts.len() - (last + 1 - first);
    }
    println!("{accepted_total} periods accepted, {refused_total} refused");
}
