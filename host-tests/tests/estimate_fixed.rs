//! The estimator in fixed point (Q17.14, the images for cores without an FPU): the same tracks
//! as f32 to within a thousandth of r_p, exact fixes handed to the law as `Limits::states`
//! would hand them, the origin kept near the own vehicle, and no fix sequence that overflows.

use twocars::estimate::{Estimated, Estimator, FieldSettings, Fix, FixNoise, Refused};
use twocars::{Error, Fixed, Guidance, Law, Limits, Policy, Scalar, Variant};
use twocars_sim::kinematics::advance;
use twocars_sim::rng::Rng;

/// The paper's limits: r_p 0.5 m, v_pm 1 m/s (a full turn in 3.14 s).
const LIMITS: [f32; 4] = [1.0, 2.0, 0.5, 1.0];
/// r_p, metres.
const R_P: f64 = 0.5;

fn settings(sigma_rp: f64, timeout: f32) -> FieldSettings {
    FieldSettings {
        target_noise: FixNoise {
            position: (sigma_rp * R_P) as f32,
            heading: (sigma_rp * R_P) as f32,
        },
        own_lead: 0.05,
        ..FieldSettings::exact(timeout)
    }
}

/// A fixed-point estimate in metres: its frame's origin plus its law units times r_p.
fn in_metres(fixed: &Estimator<Fixed>, state: [Fixed; 3]) -> [f64; 3] {
    let [ox, oy] = fixed.origin().expect("a fix");
    let metres = f64::from(fixed.units().metres);
    [
        f64::from(ox) + state[0].to_f64() * metres,
        f64::from(oy) + state[1].to_f64() * metres,
        state[2].to_f64(),
    ]
}

fn angle_apart(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

#[test]
fn fixed_point_tracks_agree_with_f32_within_a_thousandth_of_r_p() {
    // A target zigzagging every 3 s with fixes 5 Hz, 0.1 r_p of noise; the own vehicle at
    // v_pm on a wide circle, fixed every 20 ms, 150 s: it runs 300 r_p, so the fixed-point
    // frame's origin, moved where the own vehicle is 50 r_p from it, moves 5 times or more.
    let s = settings(0.1, 1.0);
    let mut float = Estimator::new(LIMITS, s).expect("valid");
    let mut fixed = Estimator::<Fixed>::with_backend(LIMITS, s).expect("valid");
    let mut rng = Rng::new(11);
    let (mut own, mut target) = ([0.0, 0.0, 0.0], [6.0, 3.0, 1.0]);
    let (mut worst, mut worst_heading, mut worst_spread) = (0.0f64, 0.0f64, 0.0f64);
    let (mut origins, mut last_origin) = (0, None);
    for k in 0..7_500u32 {
        let t = f64::from(k) * 0.02;
        let time_us = k * 20_000;
        let own_fix = Fix {
            state: own.map(|v: f64| v as f32),
            time_us,
        };
        assert_eq!(float.own_fix(&own_fix), fixed.own_fix(&own_fix));
        if k % 10 == 0 {
            let sigma = 0.1 * R_P;
            let noisy = [
                target[0] + sigma * rng.normal(),
                target[1] + sigma * rng.normal(),
                target[2] + sigma * rng.normal(),
            ];
            let fix = Fix {
                state: noisy.map(|v| v as f32),
                time_us,
            };
            assert_eq!(float.target_fix(&fix), fixed.target_fix(&fix), "fix {k}");
        }
        let (a, b) = (float.states(time_us), fixed.states(time_us));
        let (Ok(a), Ok(b)) = (a, b) else {
            panic!("step {k}: {a:?} against {b:?}");
        };
        for (f, q) in [(a.own, b.own), (a.target, b.target)] {
            let q = in_metres(&fixed, q);
            let apart = (f64::from(f[0]) - q[0]).hypot(f64::from(f[1]) - q[1]);
            worst = worst.max(apart / R_P);
            worst_heading = worst_heading.max(angle_apart(f64::from(f[2]), q[2]));
        }
        let spread = b.uncertainty.to_f64() * R_P;
        let relative = (spread - f64::from(a.uncertainty)).abs() / f64::from(a.uncertainty);
        worst_spread = worst_spread.max(relative);
        if fixed.origin() != last_origin {
            origins += 1;
            last_origin = fixed.origin();
        }
        own = advance(own, 1.0, 0.002, 0.02);
        let turn = if (t / 3.0).floor() as i64 % 2 == 0 {
            1.0
        } else {
            -1.0
        };
        target = advance(target, 0.5, turn * 0.5, 0.02);
    }
    assert!(worst < 1e-3, "positions apart by up to {worst} r_p");
    assert!(
        worst_heading < 1e-3,
        "headings apart by up to {worst_heading} rad"
    );
    assert!(
        worst_spread < 5e-3,
        "uncertainties apart by up to {worst_spread} of f32's"
    );
    assert!(origins >= 5, "the origin moved {origins} times");
    eprintln!("apart: {worst:.5} r_p, {worst_heading:.5} rad, uncertainty {worst_spread:.5}; {origins} origins");
}

/// Both estimators' law-frame states of exact fixes of `own` and `target` taken at once.
fn law_frame(
    fixed: &mut Estimator<Fixed>,
    limits: &Limits<Fixed>,
    own: [f32; 3],
    target: [f32; 3],
    time_us: u32,
) -> Result<[Fixed; 5], Error> {
    fixed
        .own_fix(&Fix {
            state: own,
            time_us,
        })
        .expect("taken");
    fixed
        .target_fix(&Fix {
            state: target,
            time_us,
        })
        .expect("taken");
    let e: Estimated<Fixed> = fixed.states(time_us).expect("fresh");
    let (p, q) = limits.states_in_units(e.own, e.target)?;
    Ok([p.x, p.y, p.theta, q.x, q.y])
}

#[test]
fn exact_fixes_reach_the_fixed_point_law_as_limits_states_gives_them() {
    let limits = Limits::<Fixed>::new(LIMITS[0], LIMITS[1], LIMITS[2], LIMITS[3]).expect("valid");
    let mut fixed = Estimator::<Fixed>::with_backend(
        LIMITS,
        FieldSettings {
            own_lead: 0.0,
            ..FieldSettings::exact(1.0)
        },
    )
    .expect("valid");
    let mut rng = Rng::new(5);
    let mut worst = 0;
    for k in 0..5_000u32 {
        // Jumps across 1 km: each own fix restarts its track (exact fixes are the truth).
        let own = [
            rng.uniform(-500.0, 500.0),
            rng.uniform(-500.0, 500.0),
            rng.uniform(-9.0, 9.0),
        ];
        let target = [
            own[0] + rng.uniform(-90.0, 90.0),
            own[1] + rng.uniform(-90.0, 90.0),
            rng.uniform(-9.0, 9.0),
        ];
        let (own, target) = (own.map(|v| v as f32), target.map(|v| v as f32));
        let got = law_frame(&mut fixed, &limits, own, target, k * 10_000).expect("inside");
        let (p, q) = limits.states(own, target).expect("inside");
        assert_eq!([got[0], got[1]], [Fixed::zero(), Fixed::zero()]);
        assert_eq!(got[2], p.theta, "pursuer's heading at {k}");
        // Each offset from the frame's origin rounds once: their difference is within one
        // raw unit (2^-14 r_p) of the one rounding of `Limits::states`.
        let raw = (got[3].raw() - q.x.raw())
            .abs()
            .max((got[4].raw() - q.y.raw()).abs());
        worst = worst.max(raw);
    }
    assert!(worst <= 1, "offsets apart by {worst} raw units");
}

#[test]
fn no_fix_sequence_overflows_or_gives_an_invalid_state() {
    // Debug builds panic on a fixed-point overflow: any would fail here.
    let mut rng = Rng::new(3);
    let limits = Limits::<Fixed>::new(LIMITS[0], LIMITS[1], LIMITS[2], LIMITS[3]).expect("valid");
    let (mut states, mut decisions) = (0, 0);
    for case in 0..40 {
        let sigma = [0.0, 0.01, 1.0, 20.0, 100.0][case % 5];
        let timeout = [0.05, 1.0, 30.0, 1000.0][case % 4];
        let mut s = settings(sigma, timeout);
        s.target_lag = timeout * 0.5;
        s.own_lead = timeout * 0.25;
        s.target_noise.heading = s.target_noise.heading.min(3.0);
        let mut fixed = Estimator::<Fixed>::with_backend(LIMITS, s).expect("valid");
        let mut guidance =
            Guidance::new(Law::new(limits, Variant::Paper), 0.02, Policy::Flight).expect("valid");
        let mut time_us = rng.next_u64() as u32;
        let span = [1.0, 300.0, 1e5, 1e6][case % 4];
        for _ in 0..2_000 {
            // Steps of 1 us to past the timeout, now and then backwards.
            let step = [1.0, 2e4, 2e5, f64::from(timeout) * 1.5e6][rng.next_u64() as usize % 4];
            let back = rng.uniform(0.0, 1.0) < 0.05;
            let step = (step * rng.uniform(0.0, 1.0)) as u32;
            time_us = if back {
                time_us.wrapping_sub(step)
            } else {
                time_us.wrapping_add(step)
            };
            let mut state = || {
                [
                    rng.uniform(-span, span) as f32,
                    rng.uniform(-span, span) as f32,
                    rng.uniform(-1e4, 1e4) as f32,
                ]
            };
            let (own, target) = (state(), state());
            let _ = fixed.own_fix(&Fix {
                state: own,
                time_us,
            });
            let _ = fixed.target_fix_received(target, time_us);
            if let Ok(e) = fixed.states(time_us) {
                let all = e.own.iter().chain(&e.target).chain([&e.uncertainty]);
                assert!(all.into_iter().all(|v| v.is_valid()), "{e:?}");
                states += 1;
                if let Ok(d) = guidance.decide_estimated(&e) {
                    assert!(d.command.pursuer.is_valid(), "{d:?}");
                    decisions += 1;
                }
            }
        }
    }
    // Not vacuous: most cases carry states, and the law decides on them.
    assert!(
        states > 20_000 && decisions > 10_000,
        "{states} states, {decisions} decisions"
    );
}

#[test]
fn fixes_beyond_fixed_points_range_are_refused_and_the_track_goes_on() {
    let mut fixed = Estimator::<Fixed>::with_backend(LIMITS, settings(0.1, 1.0)).expect("valid");
    let at = |x: f32, t| Fix {
        state: [x, 0.0, 0.0],
        time_us: t,
    };
    fixed.own_fix(&at(0.0, 0)).expect("taken");
    // 6,400 r_p is 3.2 km at the paper's r_p: a target 4 km away is out of range.
    assert_eq!(fixed.target_fix(&at(4_000.0, 0)), Err(Refused::OutOfRange));
    assert_eq!(fixed.target_fix(&at(f32::NAN, 0)), Err(Refused::NonFinite));
    fixed.target_fix(&at(10.0, 0)).expect("taken");
    assert_eq!(fixed.counters().refused, 2);
    let e = fixed.states(100_000).expect("fresh");
    assert!((e.target[0].to_f64() * R_P - 10.075).abs() < 0.01, "{e:?}");
}

#[test]
fn settings_beyond_fixed_points_envelope_are_refused() {
    // 250 r_p of noise: f32 takes it, fixed point (200 r_p) does not.
    let s = settings(250.0, 1.0);
    assert!(Estimator::new(LIMITS, s).is_ok());
    assert_eq!(
        Estimator::<Fixed>::with_backend(LIMITS, s).err(),
        Some(Error::OutOfRange)
    );
    // A pursuer turning 100 rad/s (v 10 m/s, r_p 0.1 m): past 32 rad/s.
    let fast = [10.0, 10.0, 1.0, 1.0];
    let exact = FieldSettings::exact(1.0);
    assert!(Estimator::new(fast, exact).is_ok());
    assert_eq!(
        Estimator::<Fixed>::with_backend(fast, exact).err(),
        Some(Error::OutOfRange)
    );
}
