//! GIVEN the paper's limits and its four initial states, WHEN the law is evaluated, THEN it gives
//! the values computed independently in f64 (to 1e-3 s) and the choices of the paper's figures.

mod common;

use twocars::law::{evaluate_observation, Observation};
use twocars::{Direction, Evaluation, Scalar, Status, Variant};
use twocars_sim::reference;
use twocars_sim::scenarios::{paper_cases, Case, PAPER_LIMITS};

const TOLERANCE: f64 = 1e-3;

fn evaluate<S: Scalar>(case: &Case, variant: Variant) -> Evaluation<S> {
    let observation = Observation {
        limits: PAPER_LIMITS.map(|v| v as f32),
        pursuer: case.pursuer.map(|v| v as f32),
        evader: case.evader.map(|v| v as f32),
    };
    evaluate_observation::<S>(&observation, variant)
}

fn upper<S: Scalar>(e: &Evaluation<S>) -> f64 {
    e.report
        .and_then(|r| r.solution.upper)
        .map_or(f64::INFINITY, |v| e.units.seconds(v))
}

fn check_values<S: Scalar>() {
    check_values_within::<S>(TOLERANCE);
}

/// The four upper values within `tolerance` seconds, with the f32 law's choices of circles.
fn check_values_within<S: Scalar>(tolerance: f64) {
    for case in paper_cases() {
        let e = evaluate::<S>(&case, Variant::Paper);
        assert_eq!(e.status, Status::Ok, "{}", case.name);
        let got = upper(&e);
        println!(
            "{}: upper {got:.4} s, f64 {:.4} s",
            case.name, case.expected_value
        );
        assert!(
            (got - case.expected_value).abs() < tolerance,
            "{}: upper {got} vs {}",
            case.name,
            case.expected_value
        );
        let choice = |e: &Evaluation<S>| e.report.map(|r| (r.solution.row, r.solution.col));
        let f32_choice = evaluate::<f32>(&case, Variant::Paper)
            .report
            .map(|r| (r.solution.row, r.solution.col));
        assert_eq!(choice(&e), f32_choice, "{}", case.name);
    }
}

#[test]
fn fixed_point_law_reproduces_the_four_paper_values() {
    check_values::<twocars::num::fixed::Fixed>();
}

#[test]
fn micromath_law_makes_the_paper_choices_with_its_cruder_values() {
    // No bound is promised for micromath: its values sit 0.07 to 0.25 s off on these cases.
    check_values_within::<twocars::num::micro::Micro>(0.5);
}

#[test]
fn f32_law_reproduces_the_four_paper_values() {
    check_values::<f32>();
}

#[test]
fn f64_law_reproduces_the_four_paper_values() {
    check_values::<f64>();
}

#[test]
fn independent_reference_reproduces_the_four_paper_values() {
    for case in paper_cases() {
        let s = common::Scene {
            limits: PAPER_LIMITS,
            pursuer: case.pursuer,
            evader: case.evader,
        };
        let (p, e) = s.reference();
        let g = reference::game(&p, &e);
        assert!(
            (g.upper - case.expected_value).abs() < TOLERANCE,
            "{}: {}",
            case.name,
            g.upper
        );
    }
}

#[test]
fn chosen_circles_match_the_paper_figures() {
    use Direction::{Anticlockwise as A, Clockwise as C};
    let want = [(A, A), (C, C), (A, A), (A, C)];
    for (case, (row, col)) in paper_cases().iter().zip(want) {
        let e = evaluate::<f32>(case, Variant::Paper);
        let s = e.report.expect("report").solution;
        assert_eq!((s.row, s.col), (row, col), "{}", case.name);
        assert!(
            (e.command.pursuer - row.sigma::<f32>() * 2.0).abs() < 1e-6
                && (e.command.evader - col.sigma::<f32>()).abs() < 1e-6,
            "{}: command {:?}",
            case.name,
            e.command
        );
    }
}

#[test]
fn case_three_has_no_pure_saddle_and_an_exact_double_tie() {
    let e = evaluate::<f32>(&paper_cases()[2], Variant::Paper);
    let r = e.report.expect("report");
    let s = r.solution;
    assert!(!s.saddle());
    let lower = s.lower.expect("finite lower");
    assert!(
        (f64::from(lower) - 4.5123).abs() < TOLERANCE,
        "lower {lower}"
    );
    let [[aa, ac], [ca, cc]] = r
        .matrix()
        .entries
        .map(|row| row.map(|v| v.expect("finite")));
    assert!(twocars::law::game::ties(aa, cc), "t_aa {aa} vs t_cc {cc}");
    assert!(twocars::law::game::ties(ac, ca), "t_ac {ac} vs t_ca {ca}");
    // Both rows and both columns tie: both choices go to A.
    assert_eq!(
        (s.row, s.col),
        (Direction::Anticlockwise, Direction::Anticlockwise)
    );
    let mixed = r.matrix().mixed_value().expect("mixed value");
    assert!(
        mixed > f64::from(lower) && mixed < f64::from(s.upper.expect("upper")),
        "mixed {mixed}"
    );
}

#[test]
fn case_four_keeps_the_literal_overshoot_entry_or_clamps_it() {
    let case = &paper_cases()[3];
    let paper = evaluate::<f32>(case, Variant::Paper)
        .report
        .expect("report");
    let entry = paper.pairs[1][0].expect("t_ca exists");
    assert!(entry.capture.overshoot);
    assert!(
        (f64::from(entry.capture.value) + 0.2580).abs() < TOLERANCE,
        "t_ca {:?}",
        entry.capture
    );
    let clamped = evaluate::<f32>(case, Variant::Clamped)
        .report
        .expect("report");
    let entry = clamped.pairs[1][0].expect("t_ca exists");
    assert!(entry.capture.overshoot);
    let limits = twocars::Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).unwrap();
    assert_eq!(entry.capture.value, entry.capture.turn_times(&limits).1);
    assert!(entry.capture.value >= 0.0);
    // Clamping raises a row-C entry that was not the row's max, so the value stays 5.9778.
    assert!((upper::<f32>(&evaluate::<f32>(case, Variant::Clamped)) - 5.9778).abs() < TOLERANCE);
}
