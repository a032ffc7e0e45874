//! The sampled command: turn by the angle still to go, at most the full rate over one period;
//! straight on the tangent; keep the previous choice on ties.

use twocars::{Direction, Guidance, Law, Limits, Status, Variant, VehicleState};

const PI: f32 = core::f32::consts::PI;

fn guidance(dt: f32) -> Guidance<f32> {
    let limits = Limits::new(2.0, 2.0, 1.0, 1.0).expect("paper limits");
    Guidance::new(Law::new(limits, Variant::Paper), dt, twocars::Policy::Paper)
        .expect("valid period")
}

/// A state on the f32 backend, whose frame is metres and radians.
fn state(x: f32, y: f32, theta: f32) -> VehicleState<f32> {
    VehicleState { x, y, theta }
}

#[test]
fn far_from_the_tangent_the_command_is_full_curvature() {
    let mut g = guidance(0.01);
    let e = g.step(&state(0.0, 0.0, PI / 2.0), &state(-3.0, -6.0, PI / 2.0));
    assert_eq!(e.status, Status::Ok);
    assert_eq!((e.command.pursuer, e.command.evader), (2.0, 1.0));
}

#[test]
fn near_the_tangent_the_command_turns_exactly_the_angle_left() {
    // A tail chase with the pursuer 0.01 rad right of the common line: it turns left by 0.01 rad
    // within one period, w = alpha / (v dt) = 0.01 / (2 * 0.1) = 0.05 1/m.
    let mut g = guidance(0.1);
    let e = g.step(&state(0.0, 0.0, -0.01), &state(20.0, 0.0, 0.0));
    let pair = e
        .report
        .expect("report")
        .chosen_pair()
        .copied()
        .expect("pair");
    let alpha = pair.capture.pursuer_arc;
    assert!(alpha > 0.0 && alpha < 0.02, "alpha {alpha}");
    assert!(
        (e.command.pursuer - alpha / (2.0 * 0.1)).abs() < 1e-6,
        "{:?}",
        e.command
    );
    assert!(e.command.pursuer.abs() < 2.0);
}

#[test]
fn on_a_common_line_both_go_straight_and_keep_their_choice() {
    let mut g = guidance(0.01);
    let first = g.step(&state(0.0, 0.0, 0.0), &state(20.0, 0.0, 0.0));
    assert_eq!((first.command.pursuer, first.command.evader), (0.0, 0.0));
    let s = first.report.expect("report").solution;
    assert_eq!(
        (s.row, s.col),
        (Direction::Anticlockwise, Direction::Anticlockwise)
    );
    // All four entries tie: a caller that held (C, C) keeps it; the stateless law goes to A.
    let mut held = guidance(0.01);
    for _ in 0..3 {
        let e = held.step(&state(0.0, 0.0, 0.0), &state(20.0, 0.0, 0.0));
        assert_eq!(e.command.pursuer, 0.0);
    }
    let mut c = guidance(0.01);
    // Steer the held choice to C with a state that prefers C, then return to the tie.
    let prefer_c = c.step(&state(0.0, 0.0, PI / 2.0), &state(6.0, 3.0, PI / 2.0));
    assert_eq!(
        prefer_c.report.expect("report").solution.row,
        Direction::Clockwise
    );
    let tie = c.step(&state(0.0, 0.0, 0.0), &state(20.0, 0.0, 0.0));
    let s = tie.report.expect("report").solution;
    assert_eq!((s.row, s.col), (Direction::Clockwise, Direction::Clockwise));
}

#[test]
fn a_hair_past_the_tangent_counts_as_on_it() {
    // Pursuer 1e-4 rad left of the line: for the A circle the angle to go is 2 pi - 1e-4, within
    // one period's turn (v w dt = 0.04 rad) of 2 pi, so it is on the tangent and goes straight.
    let mut g = guidance(0.01);
    let e = g.step(&state(0.0, 0.0, 1.0e-4), &state(20.0, 0.0, 0.0));
    let r = e.report.expect("report");
    let aa = r.pairs[0][0].expect("AA");
    assert_eq!(aa.capture.pursuer_arc, 0.0);
}

#[test]
fn invalid_periods_are_refused() {
    let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).expect("paper limits");
    for dt in [0.0, -1.0, f32::NAN, f32::INFINITY, 1.0e4] {
        assert!(
            Guidance::new(Law::new(limits, Variant::Paper), dt, twocars::Policy::Paper).is_err(),
            "{dt}"
        );
    }
}

#[test]
fn a_new_period_is_a_fresh_guidance_that_keeps_its_memory() {
    let law = |dt: f32| {
        let limits = Limits::new(2.0, 2.0, 1.0, 1.0).expect("paper limits");
        Guidance::new(
            Law::new(limits, Variant::Paper),
            dt,
            twocars::Policy::Flight,
        )
        .and_then(|g| g.with_capture_radius(0.3))
        .expect("valid")
    };
    // Without memory, a guidance moved to 0.05 s is one built at 0.05 s.
    let mut moved = law(0.01);
    moved.set_period(0.05).expect("valid period");
    assert_eq!(moved, law(0.05));
    // With memory (a choice made, the near field entered), a round trip gives it back.
    let mut g = law(0.01);
    for k in 0..50 {
        let t = k as f32 * 0.01;
        let _ = g.step(&state(2.0 * t, 0.0, 0.0), &state(1.0 + t, 0.5, 0.3));
    }
    let before = g;
    assert_ne!(before, law(0.01), "the chase leaves memory to keep");
    g.set_period(0.05).expect("valid period");
    assert_ne!(g, before);
    g.set_period(0.01).expect("valid period");
    assert_eq!(g, before);
    // A refused period leaves the guidance as it was.
    assert!(g.set_period(f32::NAN).is_err());
    assert_eq!(g, before);
    assert_eq!(before.with_period(0.01), Ok(before));
}
