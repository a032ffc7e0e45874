//! Seeded property tests of the law's invariants over random states and limits.

mod common;

use common::{relative_error, scene, seeded_runner, Scene};
use proptest::prelude::*;
use twocars::{law::game::ties, Direction, Law, Scalar, Status, VehicleState};
use twocars_sim::reference;

const CASES: u32 = 2000;

fn ok_report<S: Scalar>(s: &Scene) -> Option<twocars::GameReport<S>> {
    let (law, p, e) = s.law::<S>();
    let ev = law.evaluate(&p, &e);
    match ev.status {
        Status::Ok => ev.report,
        _ => None,
    }
}

#[test]
fn tangent_points_lie_on_their_circles_and_run_in_their_directions() {
    seeded_runner(CASES)
        .run(&scene(30.0), |s| {
            let (law, p, e) = s.law::<f64>();
            let Some(r) = law.evaluate(&p, &e).report else {
                return Ok(());
            };
            let pursuer_circles = twocars::TurningCircle::both(&p, &law.limits.pursuer);
            let evader_circles = twocars::TurningCircle::both(&e, &law.limits.evader);
            for (i, pc) in pursuer_circles.iter().enumerate() {
                for (j, ec) in evader_circles.iter().enumerate() {
                    let Some(pair) = r.pairs[i][j] else { continue };
                    let t = pair.tangent;
                    let u = (t.heading.cos(), t.heading.sin());
                    let (pursuer_point, evader_point) = t.points(pc, ec);
                    for (c, point) in [(pc, pursuer_point), (ec, evader_point)] {
                        let radial = (
                            (point.x - c.centre().x) / c.radius,
                            (point.y - c.centre().y) / c.radius,
                        );
                        let norm = radial.0.hypot(radial.1);
                        assert!((norm - 1.0).abs() < 1e-9, "point off its circle: {norm}");
                        // Algorithm 1: tangent = radius turned by +pi/2 (A) or -pi/2 (C).
                        let sigma: f64 = c.direction.sigma();
                        let want = (-sigma * radial.1, sigma * radial.0);
                        assert!(
                            want.0 * u.0 + want.1 * u.1 > 1.0 - 1e-9,
                            "tangent against the turn"
                        );
                    }
                    let run = (
                        evader_point.x - pursuer_point.x,
                        evader_point.y - pursuer_point.y,
                    );
                    assert!((run.0.hypot(run.1) - t.length).abs() < 1e-9 * (1.0 + t.length));
                    assert!(
                        (run.0 * u.1 - run.1 * u.0).abs() < 1e-9 * (1.0 + t.length),
                        "not along u"
                    );
                    assert!(
                        run.0 * u.0 + run.1 * u.1 >= -1e-9,
                        "directed evader to pursuer"
                    );
                }
            }
            Ok(())
        })
        .unwrap();
}

/// Position of a vehicle that turns on its circle for `t_turn` seconds and then runs straight.
fn open_loop(state: [f64; 3], v: f64, w: f64, sigma: f64, t_turn: f64, t: f64) -> (f64, f64) {
    let [x, y, theta] = state;
    let t1 = t.min(t_turn);
    let turned = theta + sigma * v * w * t1;
    let r = 1.0 / w;
    let (cx, cy) = (x - sigma * r * theta.sin(), y + sigma * r * theta.cos());
    let (px, py) = (cx + sigma * r * turned.sin(), cy - sigma * r * turned.cos());
    let straight = (t - t1).max(0.0) * v;
    (px + straight * turned.cos(), py + straight * turned.sin())
}

#[test]
fn algorithm_two_equals_an_open_loop_simulation_of_both_paths() {
    seeded_runner(CASES)
        .run(&scene(30.0), |s| {
            let (law, p, e) = s.law::<f64>();
            let Some(r) = law.evaluate(&p, &e).report else {
                return Ok(());
            };
            let [v_pm, w_pm, v_em, w_em] = s.as_f32_rounded().limits;
            let s32 = s.as_f32_rounded();
            for (i, dp) in Direction::BOTH.iter().enumerate() {
                for (j, de) in Direction::BOTH.iter().enumerate() {
                    let Some(pair) = r.pairs[i][j] else { continue };
                    let c = pair.capture;
                    if c.overshoot {
                        continue;
                    }
                    let t = c.value;
                    let (t_p, t_e) = c.turn_times(&law.limits);
                    let pp = open_loop(s32.pursuer, v_pm, w_pm, dp.sigma(), t_p, t);
                    let pe = open_loop(s32.evader, v_em, w_em, de.sigma(), t_e, t);
                    let gap = (pp.0 - pe.0).hypot(pp.1 - pe.1);
                    assert!(
                        gap < 1e-6 * (1.0 + t * v_pm),
                        "pair {i}{j}: positions {gap} apart at T = {t}"
                    );
                }
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn upper_value_is_at_least_the_lower_value() {
    seeded_runner(CASES)
        .run(&scene(30.0), |s| {
            if let Some(r) = ok_report::<f32>(&s) {
                let (u, l) = (r.solution.upper.unwrap(), r.solution.lower.unwrap());
                assert!(u >= l || ties(u, l), "upper {u} < lower {l}");
            }
            Ok(())
        })
        .unwrap();
}

fn mirrored(s: &Scene) -> Scene {
    let m = |[x, y, th]: [f64; 3]| [x, -y, -th];
    Scene {
        limits: s.limits,
        pursuer: m(s.pursuer),
        evader: m(s.evader),
    }
}

#[test]
fn mirroring_about_the_x_axis_swaps_a_and_c() {
    seeded_runner(CASES)
        .run(&scene(30.0), |s| {
            let (Some(a), Some(b)) = (ok_report::<f64>(&s), ok_report::<f64>(&mirrored(&s))) else {
                return Ok(());
            };
            for i in 0..2 {
                for j in 0..2 {
                    match (a.matrix().entries[i][j], b.matrix().entries[1 - i][1 - j]) {
                        (Some(x), Some(y)) => {
                            assert!((x - y).abs() < 1e-6 * (1.0 + x.abs()), "{x} vs {y}")
                        }
                        (None, None) => {}
                        // An arc within rounding of 0 or 2 pi can flip: allow it only there.
                        (x, y) => panic!("entry {i}{j}: {x:?} vs mirrored {y:?}"),
                    }
                }
            }
            let (sa, sb) = (a.solution, b.solution);
            assert!(
                (sa.upper.unwrap() - sb.upper.unwrap()).abs()
                    < 1e-6 * (1.0 + sa.upper.unwrap().abs())
            );
            let worst = |r: [Option<f64>; 2]| r[0].zip(r[1]).map(|(x, y)| x.max(y));
            if let [Some(r0), Some(r1)] = a.matrix().entries.map(worst) {
                if !ties(r0, r1) {
                    assert_ne!(sa.row, sb.row, "row should swap: {r0} vs {r1}");
                }
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn translating_and_rotating_the_scene_changes_no_value() {
    let moved = (
        scene(30.0),
        -100.0f64..100.0,
        -100.0f64..100.0,
        -3.0f64..3.0,
    );
    seeded_runner(CASES)
        .run(&moved, |(s, dx, dy, phi)| {
            let (c, sn) = (phi.cos(), phi.sin());
            let t = |[x, y, th]: [f64; 3]| [c * x - sn * y + dx, sn * x + c * y + dy, th + phi];
            let s2 = Scene {
                limits: s.limits,
                pursuer: t(s.pursuer),
                evader: t(s.evader),
            };
            let exact = |s: &Scene| {
                let (law, p, e) = s.law_exact();
                let ev = law.evaluate(&p, &e);
                ev.report.filter(|_| ev.status == Status::Ok)
            };
            let (Some(a), Some(b)) = (exact(&s), exact(&s2)) else {
                return Ok(());
            };
            let (ua, ub) = (a.solution.upper.unwrap(), b.solution.upper.unwrap());
            assert!(
                (ua - ub).abs() < 1e-6 * (1.0 + ua.abs()),
                "upper {ua} vs {ub}"
            );
            let (la, lb) = (a.solution.lower.unwrap(), b.solution.lower.unwrap());
            assert!(
                (la - lb).abs() < 1e-6 * (1.0 + la.abs()),
                "lower {la} vs {lb}"
            );
            Ok(())
        })
        .unwrap();
}

/// Whether any arc of the reference lies within `margin` radians of 0 or 2 pi, where rounding of
/// the input alone can move a value by a full turn.
fn near_arc_wrap(g: &reference::RefGame, margin: f64) -> bool {
    g.m.iter().flatten().flatten().any(|e| {
        [e.alpha_p, e.alpha_e]
            .iter()
            .any(|a| *a < margin || *a > std::f64::consts::TAU - margin)
    })
}

#[test]
fn f64_law_agrees_with_the_independent_reference() {
    seeded_runner(CASES)
        .run(&scene(30.0), |s| {
            let s = s.as_f32_rounded();
            let (rp, re) = s.reference();
            let g = reference::game(&rp, &re);
            if near_arc_wrap(&g, 1e-6) {
                return Ok(());
            }
            let (law, p, e): (Law<f64>, VehicleState<f64>, VehicleState<f64>) = s.law();
            let ev = law.evaluate(&p, &e);
            let Some(r) = ev.report else { return Ok(()) };
            for i in 0..2 {
                for j in 0..2 {
                    let ours = r.matrix().entries[i][j];
                    let theirs = g.m[i][j].map(|e| e.value);
                    match (ours, theirs) {
                        (Some(a), Some(b)) => {
                            assert!((a - b).abs() < 1e-7 * (1.0 + b.abs()), "{i}{j}: {a} vs {b}")
                        }
                        (None, None) => {}
                        (a, b) => panic!("{i}{j}: existence differs: {a:?} vs {b:?}"),
                    }
                }
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn f32_law_values_are_within_1e_4_relative_of_the_independent_reference() {
    let worst_upper = std::cell::Cell::new(0.0f64);
    let worst_entry = std::cell::Cell::new(0.0f64);
    let checked = std::cell::Cell::new(0usize);
    seeded_runner(CASES)
        .run(&scene(30.0), |s| {
            let s = s.as_f32_rounded();
            let (rp, re) = s.reference();
            let g = reference::game(&rp, &re);
            // Within 1e-6 of a tangent's existence limit (L^2 against |D|^2) an entry may be a
            // time in f32 and infinity in f64, or the reverse.
            let near_existence = reference::pair_terms(&rp, &re)
                .iter()
                .flatten()
                .any(|&(length_sq, d)| length_sq.abs() < 1e-6 * d * d);
            if near_arc_wrap(&g, 1e-3) || near_existence || !g.upper.is_finite() {
                return Ok(());
            }
            let Some(r) = ok_report::<f32>(&s) else {
                return Ok(());
            };
            let (upper, lower) = (r.solution.upper.unwrap(), r.solution.lower);
            let rel = relative_error(f64::from(upper), g.upper);
            worst_upper.set(worst_upper.get().max(rel));
            assert!(rel <= 1e-4, "upper {upper} vs reference {}", g.upper);
            let lower = lower.map_or(f64::INFINITY, f64::from);
            if g.lower.is_finite() || lower.is_finite() {
                let rel = relative_error(lower, g.lower);
                assert!(rel <= 1e-4, "lower {lower} vs reference {}", g.lower);
            }
            for (i, row) in r.matrix().entries.iter().enumerate() {
                for (j, ours) in row.iter().enumerate() {
                    match (ours, &g.m[i][j]) {
                        (Some(ours), Some(theirs)) => {
                            let rel = relative_error(f64::from(*ours), theirs.value);
                            worst_entry.set(worst_entry.get().max(rel));
                            assert!(rel <= 1e-4, "entry {i}{j}: {ours} vs {}", theirs.value);
                        }
                        (None, None) => {}
                        (ours, theirs) => panic!("entry {i}{j}: {ours:?} vs {theirs:?}"),
                    }
                }
            }
            checked.set(checked.get() + 1);
            Ok(())
        })
        .unwrap();
    let checked = checked.get();
    println!(
        "f32 vs reference: {checked} states, worst relative value error (floor 1 s): upper {:.2e}, \
         any entry {:.2e}",
        worst_upper.get(),
        worst_entry.get()
    );
    assert!(
        checked > CASES as usize / 2,
        "too few states checked: {checked}"
    );
}

/// The matrix game by its definition, `None` as infinity: upper is the min over rows of each
/// row's max, lower the max over columns of each column's min (the contract's values, whichever
/// option a tie chooses); the pursuer's row reaches upper, the evader's column lower, and options
/// tied within the band or `floor` go to `previous`, else A. With it, whether it is a saddle:
/// upper and lower tied within the band, or both infinite.
fn game_by_definition<S: Scalar>(
    entries: [[Option<S>; 2]; 2],
    previous: Option<(Direction, Direction)>,
    floor: S,
) -> (twocars::GameSolution<S>, bool) {
    use twocars::law::game::ties_within;
    let choose = |options: [Option<S>; 2], smaller: bool, previous: Option<Direction>| {
        let a_wins = match options {
            [None, None] => None,
            [Some(_), None] => Some(smaller),
            [None, Some(_)] => Some(!smaller),
            [Some(x), Some(y)] if ties_within(x, y, floor) => None,
            [Some(x), Some(y)] => Some((x < y) == smaller),
        };
        let choice = match a_wins {
            Some(true) => Direction::Anticlockwise,
            Some(false) => Direction::Clockwise,
            None => previous.unwrap_or(Direction::Anticlockwise),
        };
        // The extreme itself: with `None` as infinity, the min is the finite one (or either
        // finite one's min), the max is infinity if either is.
        let value = match options {
            [Some(x), Some(y)] if smaller => Some(if y < x { y } else { x }),
            [Some(x), Some(y)] => Some(if y > x { y } else { x }),
            [x, y] if smaller => x.or(y),
            _ => None,
        };
        (choice, value)
    };
    let [[aa, ac], [ca, cc]] = entries;
    let worst = |a: Option<S>, b: Option<S>| a.zip(b).map(|(a, b)| a.max(b));
    let best = |a: Option<S>, b: Option<S>| match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    let (row, upper) = choose([worst(aa, ac), worst(ca, cc)], true, previous.map(|p| p.0));
    let (col, lower) = choose([best(aa, ca), best(ac, cc)], false, previous.map(|p| p.1));
    let saddle = match (upper, lower) {
        (Some(u), Some(l)) => ties(u, l),
        (u, l) => u.is_none() && l.is_none(),
    };
    let solution = twocars::GameSolution {
        row,
        col,
        upper,
        lower,
    };
    (solution, saddle)
}

/// Every pattern of infinite entries, ties and previous choices, on each backend: the solver
/// (which carries infinity as [`Scalar::never`]) gives the game's definition. Values span each
/// backend's capture times, fixed point's extremes included (debug builds check its arithmetic
/// for overflow).
fn matrix_game_matches_its_definition<S: Scalar>() {
    let times = prop::sample::select(vec![
        -2.6e4f32, -0.258, 0.0, 1.0, 1.000_05, 1.01, 5.0, 6.5e3,
    ]);
    let entry = prop::option::weighted(0.7, times);
    let direction = prop::sample::select(vec![Direction::Anticlockwise, Direction::Clockwise]);
    let strategy = (
        [entry.clone(), entry.clone(), entry.clone(), entry],
        prop::option::of((direction.clone(), direction)),
        prop::sample::select(vec![0.0f32, 0.02]),
    );
    seeded_runner(CASES)
        .run(&strategy, |([aa, ac, ca, cc], previous, floor)| {
            let s = |v: Option<f32>| v.map(S::from_f32);
            let entries = [[s(aa), s(ac)], [s(ca), s(cc)]];
            let floor = S::from_f32(floor);
            let game = twocars::MatrixGame { entries };
            let got = game.solve_sampled(previous, floor);
            let (solution, saddle) = game_by_definition(entries, previous, floor);
            assert_eq!(got, solution, "{entries:?}");
            assert_eq!(got.saddle(), saddle, "{entries:?}");
            Ok(())
        })
        .unwrap();
}

#[test]
fn matrix_game_with_infinite_entries_is_solved_as_defined_on_every_backend() {
    matrix_game_matches_its_definition::<f32>();
    matrix_game_matches_its_definition::<f64>();
    matrix_game_matches_its_definition::<twocars::num::fixed::Fixed>();
}

/// The contract's tie band on one backend: two values tie only if they differ by at most
/// `S::TIE_BAND` (at most 1e-4) of the larger magnitude, and do tie when they differ by less than
/// half of it (less the backend's resolution, `resolution` seconds). Values near each other
/// across the capture times' range, both signs, compared in f64 as the backend holds them.
fn tie_band_is_as_documented<S: Scalar>(resolution: f64) {
    assert!(S::TIE_BAND <= 1.0e-4, "band {}", S::TIE_BAND);
    let band = f64::from(S::TIE_BAND);
    let strategy = (
        prop::sample::select(vec![
            -2.6e4f64, -3.0, -0.258, 0.3, 0.5, 1.0, 5.657, 100.0, 6.5e3,
        ]),
        -3.0 * band..3.0 * band,
    );
    seeded_runner(CASES)
        .run(&strategy, |(a, relative)| {
            let (a, b) = (
                S::from_f32(a as f32),
                S::from_f32((a * (1.0 + relative)) as f32),
            );
            let (x, y) = (a.to_f64(), b.to_f64());
            let (difference, larger) = ((x - y).abs(), x.abs().max(y.abs()));
            if ties(a, b) {
                // A thousandth of the band for the f32 subtraction's rounding.
                assert!(
                    difference <= band * 1.001 * larger,
                    "{x} and {y} tie: {:.3e} relative",
                    difference / larger
                );
            } else {
                assert!(
                    difference + resolution > 0.5 * band * larger,
                    "{x} and {y} do not tie: {:.3e} relative",
                    difference / larger
                );
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn tie_band_is_as_documented_on_every_backend() {
    tie_band_is_as_documented::<f32>(0.0);
    tie_band_is_as_documented::<f64>(0.0);
    tie_band_is_as_documented::<twocars::num::micro::Micro>(0.0);
    tie_band_is_as_documented::<twocars::num::fixed::Fixed>(2.0 / 16_384.0);
}

/// Near capture, each backend's status follows the contract's capture radius (1e-6 r_p): the
/// players are `captured` only within it; beyond it they are played, or on fixed point, where
/// both offsets are below half a raw unit (2^-15 r_p) and would round to one point,
/// `out_of_range`. Distances log-uniform from 1e-8 r_p to 0.1 r_p, in every direction, at the
/// paper's limits and a pursuer off the origin.
fn captured_only_within_the_capture_radius<S: Scalar>() {
    let r_p = 0.5f64;
    let strategy = (-8.0f64..-1.0, -3.2f64..3.2, -3.2f32..3.2);
    seeded_runner(CASES)
        .run(&strategy, |(log_distance, direction, heading)| {
            let distance = 10f64.powf(log_distance) * r_p;
            let pursuer = [3.0f32, -2.0, heading];
            let evader = [
                (3.0 + distance * direction.cos()) as f32,
                (-2.0 + distance * direction.sin()) as f32,
                -heading,
            ];
            // The offsets as the f32 inputs hold them.
            let (dx, dy) = (
                f64::from(evader[0]) - f64::from(pursuer[0]),
                f64::from(evader[1]) - f64::from(pursuer[1]),
            );
            let apart = dx.hypot(dy) / r_p;
            let observation = twocars::law::Observation {
                limits: [2.0, 2.0, 1.0, 1.0],
                pursuer,
                evader,
            };
            let status =
                twocars::law::evaluate_observation::<S>(&observation, twocars::Variant::Paper)
                    .status;
            let unresolved = S::NORMALISED && dx.abs().max(dy.abs()) / r_p < 1.0 / 32_768.0;
            match status {
                Status::Captured => {
                    assert!(apart <= 1.0e-6 * 1.001, "captured {apart:e} r_p apart")
                }
                Status::OutOfRange => assert!(unresolved, "out of range {apart:e} r_p apart"),
                Status::Ok | Status::NoValidTangent => {
                    assert!(
                        apart > 1.0e-6 * 0.999 && !unresolved,
                        "played {apart:e} r_p apart"
                    )
                }
                other => panic!("{other:?} {apart:e} r_p apart"),
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn captured_only_within_the_capture_radius_on_every_backend() {
    captured_only_within_the_capture_radius::<f32>();
    captured_only_within_the_capture_radius::<f64>();
    captured_only_within_the_capture_radius::<twocars::num::fixed::Fixed>();
}
