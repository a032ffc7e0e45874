//! The crate as a user meets it: one error type, states from metres on every backend, results
//! back in SI units.

use twocars::{Error, Fixed, Guidance, Law, Limits, Micro, Policy, Scalar, Status, Variant};

const HALF_PI: f32 = core::f32::consts::FRAC_PI_2;
/// The paper's case 1, metres and radians.
const CASE_1: ([f32; 3], [f32; 3]) = ([0.0, 0.0, HALF_PI], [-3.0, -6.0, HALF_PI]);

/// Case 1's value (s) and both turn rates (rad/s) on backend `S`, set up from SI units.
fn case_1<S: Scalar>() -> Result<(f32, [f32; 2]), Error> {
    let limits = Limits::<S>::new(2.0, 2.0, 1.0, 1.0)?;
    let mut guidance = Guidance::new(Law::new(limits, Variant::Paper), 0.01, Policy::Flight)?;
    let (pursuer, evader) = limits.states(CASE_1.0, CASE_1.1)?;
    let decision = guidance.decide(&pursuer, &evader);
    assert_eq!(decision.status, Status::Ok);
    let seconds = decision.value_seconds().ok_or(Error::OutOfRange)?;
    Ok((seconds, guidance.turn_rates(&decision)))
}

#[test]
fn every_backend_takes_metres_and_gives_seconds_and_radians_per_second() {
    let (seconds, rates) = case_1::<f32>().unwrap();
    assert!((seconds - 5.6575).abs() < 1e-3, "{seconds}");
    // Case 1: both turn anticlockwise at full rate, v_max w_max: 4 and 1 rad/s.
    assert_eq!(rates, [4.0, 1.0]);
    // Each backend within its documented error of the value (docs/numeric.md: micromath's
    // approximations are good to a few percent).
    for (name, (s, r), within) in [
        ("fixed", case_1::<Fixed>().unwrap(), 2e-3),
        ("micromath", case_1::<Micro>().unwrap(), 0.05 * seconds),
        ("f64", case_1::<f64>().unwrap(), 1e-4),
    ] {
        assert!((s - seconds).abs() < within, "{name}: {s} s");
        for (a, b) in r.iter().zip(rates) {
            assert!((a - b).abs() < 1e-3, "{name}: {r:?} rad/s");
        }
    }
}

#[test]
fn curvatures_come_back_in_inverse_metres_on_fixed_point() {
    let limits = Limits::<Fixed>::new(2.0, 0.5, 1.0, 0.25).unwrap();
    let mut guidance =
        Guidance::new(Law::new(limits, Variant::Paper), 0.01, Policy::Paper).unwrap();
    let (p, e) = limits.states(CASE_1.0, [-12.0, -24.0, HALF_PI]).unwrap();
    let decision = guidance.decide(&p, &e);
    // Full anticlockwise turns: w_max of each, 1/m (the radius 2 m here is the unit).
    assert_eq!(decision.curvatures(), [0.5, 0.25]);
    assert_eq!(guidance.turn_rates(&decision), [1.0, 0.25]);
}

#[test]
fn set_up_errors_are_one_type_that_displays_and_boxes() {
    fn set_up(dt: f32) -> Result<Guidance<f32>, Box<dyn std::error::Error>> {
        let limits = Limits::new(2.0, 2.0, 1.0, 1.0)?;
        Ok(Guidance::new(
            Law::new(limits, Variant::Paper),
            dt,
            Policy::Flight,
        )?)
    }
    assert!(set_up(0.01).is_ok());
    let refused = set_up(-1.0).unwrap_err();
    assert_eq!(refused.to_string(), Error::InvalidPeriod.to_string());
    let errors = [
        Limits::<f32>::new(f32::NAN, 2.0, 1.0, 1.0).unwrap_err(),
        Limits::<f32>::new(1.0, 2.0, 2.0, 1.0).unwrap_err(),
        Limits::<f32>::new(2.0e6, 2.0, 1.0, 1.0).unwrap_err(),
        Error::InvalidPeriod,
        Error::TablesMismatch,
    ];
    let names: Vec<String> = errors.iter().map(ToString::to_string).collect();
    for (i, name) in names.iter().enumerate() {
        assert!(!name.is_empty());
        assert!(!names[..i].contains(name), "{name} said twice");
    }
    let statuses = errors.map(Error::status);
    assert_eq!(
        statuses,
        [
            Status::NonFiniteInput,
            Status::InvalidLimits,
            Status::OutOfRange,
            Status::InvalidLimits,
            Status::InvalidLimits
        ]
    );
}

#[test]
fn the_default_policy_is_the_one_to_fly() {
    assert_eq!(Policy::default(), Policy::Flight);
}
