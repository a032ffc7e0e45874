//! The estimator: fixes carried to the decision's time, noise filtered, bad fixes refused, and
//! exact fixes through it changing nothing.

use twocars::estimate::{Estimator, FieldSettings, Fix, FixNoise, Refused, Track};
use twocars::{Guidance, Law, Limits, Policy, Variant};
use twocars_sim::adversary::EvaderKind;
use twocars_sim::field::{chase, FieldModel, Receiver};
use twocars_sim::kinematics::advance;
use twocars_sim::rng::Rng;
use twocars_sim::scenarios::PAPER_LIMITS;
use twocars_sim::sim::SimParams;

const SECOND: u32 = 1_000_000;

fn fix(state: [f64; 3], t: f64) -> Fix {
    Fix {
        state: state.map(|v| v as f32),
        time_us: (t * 1e6).round() as u32,
    }
}

#[test]
fn a_circling_car_is_carried_along_its_circle_over_the_lag() {
    // v 1 m/s, turning at 0.8 rad/s: fixes every 0.2 s, asked for 0.3 s after the last one.
    let mut track = Track::new(1.0, 1.0, FixNoise::default()).expect("valid");
    let mut state = [3.0, -2.0, 0.4];
    for k in 0..6 {
        track
            .update(&fix(state, 0.2 * k as f64), SECOND)
            .expect("taken");
        state = advance(state, 1.0, 0.8, 0.2);
    }
    let truth = advance(advance(state, 1.0, 0.8, -0.2), 1.0, 0.8, 0.3);
    let (at, spread) = track.at((1.3e6) as u32, SECOND).expect("fresh");
    let error = (f64::from(at[0]) - truth[0]).hypot(f64::from(at[1]) - truth[1]);
    assert!(error < 1e-3, "{at:?} against {truth:?}: {error} m");
    assert!((f64::from(at[2]) - truth[2]).abs() < 1e-3);
    let (speed, turn) = track.rates().expect("fixes");
    assert!((speed - 1.0).abs() < 1e-3 && (turn - 0.8).abs() < 1e-3);
    // No noise: the uncertainty is the turn a car may reverse over 0.3 s, 1 * 1 * 0.09 / 2.
    assert!((spread - 0.045).abs() < 1e-3, "{spread}");
}

#[test]
fn noise_is_filtered_to_well_below_the_fixes() {
    let sigma = 0.1;
    let noise = FixNoise {
        position: sigma as f32,
        heading: sigma as f32,
    };
    let mut track = Track::new(1.0, 1.0, noise).expect("valid");
    let mut rng = Rng::new(7);
    let (mut sum_raw, mut sum_est, mut n) = (0.0, 0.0, 0.0);
    for k in 0..1000 {
        let t = 0.02 * k as f64;
        let truth = [t, 0.5, 0.0];
        let noisy = [
            truth[0] + sigma * rng.normal(),
            truth[1] + sigma * rng.normal(),
            sigma * rng.normal(),
        ];
        track.update(&fix(noisy, t), SECOND).expect("taken");
        if k >= 200 {
            let (at, _) = track.at((t * 1e6).round() as u32, SECOND).expect("fresh");
            sum_raw += (noisy[0] - truth[0]).powi(2) + (noisy[1] - truth[1]).powi(2);
            sum_est +=
                (f64::from(at[0]) - truth[0]).powi(2) + (f64::from(at[1]) - truth[1]).powi(2);
            n += 1.0;
        }
    }
    let (raw, est) = ((sum_raw / n).sqrt(), (sum_est / n).sqrt());
    assert!(
        est < 0.4 * raw,
        "rms error {est} m against the fixes' {raw} m"
    );
}

#[test]
fn a_steady_links_terms_are_those_of_its_interval() {
    // Two tracks take the same noisy fixes 0.2 s apart; one has seen fixes 0.15 s apart
    // first and been cleared. Each fix's gains are its interval's, so they agree throughout.
    let noise = FixNoise {
        position: 0.1,
        heading: 0.05,
    };
    let mut fresh = Track::new(1.0, 1.0, noise).expect("valid");
    let mut seasoned = fresh;
    let mut rng = Rng::new(11);
    let mut noisy = |t: f64| {
        [
            t + 0.1 * rng.normal(),
            0.1 * rng.normal(),
            0.05 * rng.normal(),
        ]
    };
    let mut before = 0.0;
    for k in 0..5 {
        let t = 0.15 * k as f64;
        seasoned.update(&fix(noisy(t), t), SECOND).expect("taken");
        before = seasoned
            .at((t * 1e6) as u32 + 100_000, SECOND)
            .expect("fresh")
            .1;
    }
    seasoned.clear();
    let mut carried = Vec::new();
    for k in 0..20 {
        let t = 10.0 + 0.2 * k as f64;
        let f = fix(noisy(t), t);
        fresh.update(&f, SECOND).expect("taken");
        seasoned.update(&f, SECOND).expect("taken");
        let now = f.time_us + 100_000;
        assert_eq!(fresh.at(now, SECOND), seasoned.at(now, SECOND), "fix {k}");
        carried.push(fresh.at(now, SECOND).expect("fresh").1);
    }
    // The other interval's terms leave another spread: reused, they would show.
    assert!((carried[19] - before).abs() > 1e-3, "{before} {carried:?}");
}

#[test]
fn bad_fixes_are_refused_and_a_vehicle_that_moved_is_found_again() {
    let noise = FixNoise {
        position: 0.1,
        heading: 0.05,
    };
    let mut track = Track::new(1.0, 1.0, noise).expect("valid");
    track
        .update(&fix([0.0, 0.0, 0.0], 1.0), SECOND)
        .expect("first");
    let nan = Fix {
        state: [f32::NAN, 0.0, 0.0],
        time_us: 1_100_000,
    };
    assert_eq!(track.update(&nan, SECOND), Err(Refused::NonFinite));
    assert_eq!(
        track.update(&fix([0.0, 0.0, 0.0], 0.9), SECOND),
        Err(Refused::OutOfOrder)
    );
    assert_eq!(
        track.update(&fix([0.0, 0.0, 0.0], 1.0), SECOND),
        Err(Refused::OutOfOrder)
    );
    // 50 m away after 0.1 s: refused three times, taken (a restart) the fourth.
    for k in 1..=3 {
        let far = fix([50.0, 0.0, 0.0], 1.0 + 0.1 * k as f64);
        assert_eq!(track.update(&far, SECOND), Err(Refused::Outlier));
    }
    track
        .update(&fix([50.0, 0.0, 0.0], 1.4), SECOND)
        .expect("restart");
    let (at, _) = track.at(1_400_000, SECOND).expect("fresh");
    assert_eq!(at, [50.0, 0.0, 0.0]);
}

#[test]
fn an_estimate_older_than_the_timeout_gives_no_states() {
    let limits = [2.0, 2.0, 1.0, 1.0];
    let mut estimator = Estimator::new(limits, FieldSettings::exact(0.5)).expect("valid");
    assert!(estimator.states(0).is_err());
    estimator
        .own_fix(&fix([0.0, 0.0, 0.0], 0.0))
        .expect("own fix");
    estimator
        .target_fix(&fix([5.0, 0.0, 0.0], 0.0))
        .expect("target fix");
    assert!(estimator.states(400_000).is_ok());
    assert!(estimator.states(600_000).is_err());
    let counters = estimator.counters();
    assert_eq!((counters.stale, counters.target_fixes), (2, 1));
    assert_eq!(counters.coasted, 0);
}

#[test]
fn impossible_settings_are_refused() {
    let limits = [2.0, 2.0, 1.0, 1.0];
    let with = |f: fn(&mut FieldSettings)| {
        let mut s = FieldSettings::exact(1.0);
        f(&mut s);
        Estimator::new(limits, s).is_err()
    };
    assert!(with(|s| s.timeout = 0.0));
    assert!(with(|s| s.timeout = f32::NAN));
    assert!(with(|s| s.target_lag = 1.0));
    assert!(with(|s| s.own_lead = -0.1));
    assert!(with(|s| s.target_noise.position = -1.0));
    assert!(with(|s| s.own_noise.heading = f32::INFINITY));
    assert!(Estimator::new([2.0, f32::NAN, 1.0, 1.0], FieldSettings::exact(1.0)).is_err());
    assert!(!with(|_| ()));
}

/// A seeded start 2 to 12 m from the pursuer at the paper's limits.
fn start(rng: &mut Rng) -> SimParams {
    let pi = std::f64::consts::PI;
    let d0 = rng.uniform(2.0, 12.0);
    let bearing = rng.uniform(-pi, pi);
    SimParams {
        limits: PAPER_LIMITS,
        pursuer: [0.0, 0.0, rng.uniform(-pi, pi)],
        evader: [d0 * bearing.cos(), d0 * bearing.sin(), rng.uniform(-pi, pi)],
        dt: 0.01,
        t_max: 60.0,
        eps: 0.15,
    }
}

#[test]
fn exact_fixes_through_the_estimator_change_nothing() {
    let mut rng = Rng::new(11);
    for evader in [EvaderKind::Law, EvaderKind::Straight, EvaderKind::BangBang] {
        for _ in 0..6 {
            let params = start(&mut rng);
            let seed = rng.next_u64();
            let raw = chase(&params, evader, seed, &FieldModel::EXACT, Receiver::Raw);
            let est = chase(
                &params,
                evader,
                seed,
                &FieldModel::EXACT,
                Receiver::Estimator { own_lead: 0.0 },
            );
            assert_eq!(
                raw.t_capture.to_bits(),
                est.t_capture.to_bits(),
                "{evader:?}"
            );
            assert_eq!(raw.sign_flips, est.sign_flips);
        }
    }
}

#[test]
fn the_decision_on_exact_estimates_is_the_decision_on_the_states() {
    let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).expect("valid");
    let law = Law::new(limits, Variant::Paper);
    let mut plain = Guidance::new(law, 0.01, Policy::Flight).expect("valid");
    let mut estimated = plain;
    let mut estimator =
        Estimator::new([2.0, 2.0, 1.0, 1.0], FieldSettings::exact(1.0)).expect("ok");
    let (mut p, mut e) = ([0.0, 0.0, 1.2], [-3.0, -6.0, 1.57]);
    for k in 0..300 {
        let t = 0.01 * f64::from(k);
        estimator.own_fix(&fix(p, t)).expect("own");
        estimator.target_fix(&fix(e, t)).expect("target");
        let est = estimator.states((t * 1e6).round() as u32).expect("fresh");
        assert_eq!(est.uncertainty, 0.0);
        let a = estimated.decide_estimated(&est).expect("in range");
        let (ps, es) = limits
            .states(p.map(|v| v as f32), e.map(|v| v as f32))
            .expect("in range");
        let b = plain.decide(&ps, &es);
        assert_eq!(a, b, "step {k}");
        let [wp, we] = b.curvatures();
        p = advance(p, 2.0, f64::from(wp), 0.01);
        e = advance(e, 1.0, f64::from(we), 0.01);
        p[2] = twocars_sim::kinematics::wrap_pi(p[2]);
        e[2] = twocars_sim::kinematics::wrap_pi(e[2]);
    }
}

#[test]
fn noisy_fixes_through_the_estimator_do_not_chatter() {
    // sigma 0.1 r_p on position, 0.05 rad on heading, a fix every period, lag 0.1 T.
    let field = |seed| FieldModel {
        lag: 0.157,
        position_sigma: 0.05,
        heading_sigma: 0.05,
        seed,
        ..FieldModel::EXACT
    };
    let mut rng = Rng::new(5);
    let (mut raw_flips, mut est_flips) = (Vec::new(), Vec::new());
    for _ in 0..12 {
        let params = start(&mut rng);
        let (seed, noise) = (rng.next_u64(), rng.next_u64());
        let raw = chase(
            &params,
            EvaderKind::Straight,
            seed,
            &field(noise),
            Receiver::Raw,
        );
        let est = chase(
            &params,
            EvaderKind::Straight,
            seed,
            &field(noise),
            Receiver::Estimator { own_lead: 0.0 },
        );
        assert_eq!(est.status, twocars_sim::sim::SimStatus::Captured);
        raw_flips.push(raw.sign_flips);
        est_flips.push(est.sign_flips);
    }
    raw_flips.sort_unstable();
    est_flips.sort_unstable();
    let (raw, est) = (raw_flips[6], est_flips[6]);
    assert!(raw >= 50, "the raw fixes chatter: median {raw}");
    assert!(
        est * 5 <= raw,
        "median flips {est} through the estimator, {raw} raw"
    );
}

#[test]
fn decisions_between_fixes_coast_and_are_counted() {
    let limits = [2.0, 2.0, 1.0, 1.0];
    let mut estimator = Estimator::new(limits, FieldSettings::exact(1.0)).expect("valid");
    // A target fix every 100 ms, a decision every 10 ms: 9 of each 10 decisions coast.
    for k in 0..30_u32 {
        let t = f64::from(k) * 0.01;
        estimator.own_fix(&fix([0.0, 0.0, 0.0], t)).expect("own");
        if k % 10 == 0 {
            estimator
                .target_fix(&fix([5.0 + t, 0.0, 0.0], t))
                .expect("target");
        }
        let est = estimator.states((t * 1e6).round() as u32).expect("fresh");
        // Carried on at 1 m/s: x = 5 + t whatever the age.
        assert!(
            (f64::from(est.target[0]) - (5.0 + t)).abs() < 1e-4,
            "{est:?} at {t}"
        );
    }
    let counters = estimator.counters();
    assert_eq!((counters.target_fixes, counters.coasted), (3, 27));
}

#[test]
fn sparse_noisy_fixes_of_a_straight_target_are_chased_without_orbits() {
    // 5 fixes per full turn T (0.314 s), 0.1 T late, sigma 0.2 r_p on position and 0.1 rad on
    // heading; the pursuer answers its yaw-rate setpoint with tau 0.1 T; capture at 0.3 r_p.
    let turn = std::f64::consts::TAU / 4.0;
    let field = |seed| FieldModel {
        lag: 0.1 * turn,
        fix_interval: turn / 5.0,
        position_sigma: 0.1,
        heading_sigma: 0.1,
        yaw_lag: 0.1 * turn,
        seed,
        ..FieldModel::EXACT
    };
    let mut rng = Rng::new(23);
    let (mut excess, mut loops) = (Vec::new(), 0);
    for _ in 0..20 {
        let params = start(&mut rng);
        let (seed, noise) = (rng.next_u64(), rng.next_u64());
        let lagging = FieldModel {
            yaw_lag: 0.1 * turn,
            ..FieldModel::EXACT
        };
        let exact = chase(&params, EvaderKind::Straight, seed, &lagging, Receiver::Raw);
        let est = chase(
            &params,
            EvaderKind::Straight,
            seed,
            &field(noise),
            Receiver::Estimator {
                own_lead: 0.1 * turn,
            },
        );
        assert_eq!(est.status, twocars_sim::sim::SimStatus::Captured);
        excess.push((est.t_capture - exact.t_capture) / exact.t_capture);
        loops += est.loops;
    }
    excess.sort_by(f64::total_cmp);
    let p90 = excess[17];
    assert!(p90 <= 0.25, "p90 of the excess {:+.1} %", 100.0 * p90);
    assert!(loops <= 1, "{loops} loops in 20 chases");
}

#[test]
fn a_steady_target_is_carried_straight_and_a_turning_one_on_its_arc() {
    // A car of 1 m/s and 1 rad/s fixed every 0.314 s with 0.1 m and 0.1 rad of noise; each
    // decision carries it 0.5 s past its last fix.
    let noise = FixNoise {
        position: 0.1,
        heading: 0.1,
    };
    let stale = 10_000_000;
    for turn_rate in [0.0, 1.0] {
        let mut track = Track::new(1.0, 1.0, noise).expect("valid");
        let mut rng = Rng::new(3);
        let mut turns = Vec::new();
        for k in 0..60 {
            let t = 0.314 * f64::from(k);
            let truth = advance([0.0, 0.0, 0.0], 1.0, turn_rate, t);
            let noisy = [
                truth[0] + 0.1 * rng.normal(),
                truth[1] + 0.1 * rng.normal(),
                twocars_sim::kinematics::wrap_pi(truth[2] + 0.1 * rng.normal()),
            ];
            let at = fix(noisy, t);
            track.update(&at, stale).expect("taken");
            if k >= 10 {
                let (now, _) = track.at(at.time_us, stale).expect("fresh");
                let (later, _) = track.at(at.time_us + 500_000, stale).expect("fresh");
                turns.push(f64::from(later[2] - now[2]));
            }
        }
        turns.sort_by(f64::total_cmp);
        let turning = turns.iter().filter(|t| t.abs() > 1e-6).count();
        if turn_rate == 0.0 {
            assert!(turning <= 5, "carried on an arc {turning} times of 50");
        } else {
            let median = turns[25];
            assert!((median - 0.5).abs() < 0.15, "carried {median} rad in 0.5 s");
        }
    }
}

#[test]
fn a_fix_that_carries_its_speed_sets_the_tracks_speed() {
    // A car of v_max 1 m/s running straight at 0.3 m/s, fixed every 0.314 s with 0.1 m and
    // 0.1 rad of noise; each fix is carried 0.5 s on. From positions alone the track starts
    // at v_max and learns 0.3 m/s over many fixes; from the fixes' speed it has it at once.
    let noise = FixNoise {
        position: 0.1,
        heading: 0.1,
    };
    let stale = 10_000_000;
    let error_after = |with_speed: bool| {
        let mut track = Track::new(1.0, 1.0, noise).expect("valid");
        let mut rng = Rng::new(5);
        let mut worst: f64 = 0.0;
        for k in 0..12 {
            let t = 0.314 * f64::from(k);
            let truth = advance([0.0, 0.0, 0.0], 0.3, 0.0, t);
            let noisy = [
                truth[0] + 0.1 * rng.normal(),
                truth[1] + 0.1 * rng.normal(),
                truth[2] + 0.1 * rng.normal(),
            ];
            let at = fix(noisy, t);
            if with_speed {
                track.update_with_speed(&at, 0.3, stale).expect("taken");
                let (speed, _) = track.rates().expect("a track");
                assert_eq!(speed, 0.3, "fix {k}");
            } else {
                track.update(&at, stale).expect("taken");
            }
            let (later, _) = track.at(at.time_us + 500_000, stale).expect("fresh");
            let ahead = advance([0.0, 0.0, 0.0], 0.3, 0.0, t + 0.5);
            worst = worst.max(f64::from(later[0]) - ahead[0]);
        }
        worst
    };
    let measured = error_after(true);
    let differenced = error_after(false);
    assert!(
        measured < 0.25,
        "carried {measured:.2} m ahead with the speed"
    );
    assert!(
        differenced > 2.0 * measured,
        "{differenced:.2} m ahead from positions alone, {measured:.2} m with the speed"
    );
}

#[test]
fn a_fix_speed_beyond_the_limit_is_the_limit_and_a_bad_one_is_refused() {
    let mut track = Track::new(1.0, 1.0, FixNoise::default()).expect("valid");
    let start = fix([0.0, 0.0, 0.0], 1.0);
    track.update_with_speed(&start, 3.0, SECOND).expect("taken");
    assert_eq!(track.rates(), Some((1.0, 0.0)));
    let next = fix([0.2, 0.0, 0.0], 1.2);
    for bad in [f32::NAN, f32::INFINITY, -0.1] {
        assert_eq!(
            track.update_with_speed(&next, bad, SECOND),
            Err(Refused::NonFinite),
            "{bad}"
        );
    }
    assert_eq!(track.rates(), Some((1.0, 0.0)), "unchanged by a refusal");
    let limits = PAPER_LIMITS.map(|v| v as f32);
    let mut estimator = Estimator::new(limits, FieldSettings::exact(1.0)).expect("valid");
    assert_eq!(
        estimator.target_fix_with_speed(&start, f32::NAN),
        Err(Refused::NonFinite)
    );
    assert_eq!(estimator.counters().refused, 1);
    estimator.target_fix_with_speed(&start, 0.5).expect("taken");
    assert_eq!(estimator.target().rates(), Some((0.5, 0.0)));
}
