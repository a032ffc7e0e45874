//! The integer IEEE 754 conversions of the fixed-point backend (src/num/ieee.rs,
//! src/num/convert.rs) against exact f64 references: every exponent field, both signs,
//! subnormals, NaN and the infinities.

use twocars::num::convert::{self, Reciprocal};
use twocars::num::fixed::Fixed;
use twocars::{Limits, Scalar};
use twocars_sim::rng::Rng;

/// Mantissa fields to try in every binade: the edges, and seeded random ones.
fn mantissas(rng: &mut Rng) -> Vec<u32> {
    let mut m = vec![
        0, 1, 2, 3, 0x20_0000, 0x3f_ffff, 0x40_0000, 0x40_0001, 0x7f_fffe, 0x7f_ffff,
    ];
    m.extend((0..64).map(|_| (rng.next_u64() as u32) & 0x7f_ffff));
    m
}

/// Every f32 bit pattern of the sweep: 2 signs x 256 exponent fields x the mantissas.
fn sweep() -> Vec<u32> {
    let mut rng = Rng::new(0x01ee_e754);
    let mantissas = mantissas(&mut rng);
    let mut bits = Vec::new();
    for sign in [0u32, 1 << 31] {
        for field in 0..=255u32 {
            bits.extend(mantissas.iter().map(|m| sign | field << 23 | m));
        }
    }
    bits
}

/// round(v 2^14), half away from zero, if it fits in Q17.14 (exact in f64).
fn q14_reference(v: f32) -> Option<i32> {
    if !v.is_finite() {
        return None;
    }
    let r = (f64::from(v) * 16384.0).round();
    (r.abs() < 2f64.powi(31)).then_some(r as i32)
}

#[test]
fn every_f32_converts_to_q14_rounded_once_to_nearest() {
    let (mut checked, mut invalid) = (0, 0);
    for bits in sweep() {
        let v = f32::from_bits(bits);
        let got = Fixed::from_f32(v);
        match q14_reference(v) {
            Some(raw) if raw != i32::MIN => assert_eq!(got.raw(), raw, "{v:e} ({bits:#010x})"),
            _ => {
                assert!(got.is_invalid(), "{v:e} ({bits:#010x}) gave {}", got.raw());
                invalid += 1;
            }
        }
        checked += 1;
    }
    // Half the binades are beyond 2^17, plus NaN and the infinities: the check can fail both ways.
    assert!(
        invalid > checked / 4 && invalid < checked * 3 / 4,
        "{invalid} of {checked}"
    );
    // Ties: 2.5 and -2.5 raw units round away from zero.
    assert_eq!(Fixed::from_f32(2.5 / 16384.0).raw(), 3);
    assert_eq!(Fixed::from_f32(-2.5 / 16384.0).raw(), -3);
    assert_eq!(Fixed::from_f32(0.5f32.next_down() / 16384.0).raw(), 0);
}

#[test]
fn q14_values_times_every_f32_scale_are_the_exact_product_rounded_once() {
    let mut rng = Rng::new(7);
    let mut raws: Vec<i32> = vec![0, 1, -1, 2, 16_384, -16_384, (1 << 29) - 1, -(1 << 29) + 1];
    raws.extend((0..29).flat_map(|k| [1 << k, -(1 << k), (1 << k) + 1, -(1 << k) - 1]));
    raws.extend((0..200).map(|_| (rng.next_u64() as i32) >> 3));
    let (mut compared, mut special) = (0, 0);
    for bits in sweep() {
        let scale = f32::from_bits(bits);
        for &raw in &raws {
            let got = Fixed::from_raw(raw).to_f32_scaled(scale);
            // |raw| < 2^29 and a 24-bit mantissa: the f64 product is exact, `as f32` rounds once.
            let want = (f64::from(raw) * f64::from(scale) / 16384.0) as f32;
            if want.is_nan() {
                assert!(got.is_nan(), "{raw} x {scale:e}");
                special += 1;
            } else {
                assert_eq!(
                    got.to_bits(),
                    want.to_bits(),
                    "{raw} x {scale:e}: {got:e} != {want:e}"
                );
            }
            compared += 1;
        }
    }
    assert!(
        special > 0 && compared > 1_000_000,
        "{special} of {compared}"
    );
    assert!(Fixed::from_raw(i32::MIN).to_f32().is_nan());
    assert_eq!(Fixed::from_raw(3).to_f32(), 3.0 / 16384.0);
}

#[test]
fn headings_reduce_to_the_nearest_q14_radian_in_minus_pi_to_pi() {
    let pi_q14 = Fixed::pi().raw();
    let mut worst = 0i64;
    let mut compared = 0;
    for bits in sweep() {
        let theta = f32::from_bits(bits);
        if !(theta.is_finite() && theta.abs() <= 1.0e4) {
            continue;
        }
        let got = convert::heading(theta);
        assert!((-pi_q14..=pi_q14).contains(&got), "{theta:e}: {got}");
        // f64 reduction: within 2e-12 rad for |theta| <= 1e4, far below half a raw unit.
        let tau = 2.0 * std::f64::consts::PI;
        let reduced =
            (f64::from(theta) + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI;
        let want = (reduced * 16384.0).round() as i64;
        // +-pi are the same heading.
        let diff = (i64::from(got) - want).abs();
        let diff = diff.min((diff - 2 * i64::from(pi_q14)).abs());
        worst = worst.max(diff);
        compared += 1;
    }
    assert!(compared > 15_000, "{compared}");
    assert!(worst <= 1, "worst {worst} raw units");
    assert_eq!(
        convert::heading(10.0),
        ((10.0 - 4.0 * std::f64::consts::PI) * 16384.0).round() as i32
    );
}

#[test]
fn offsets_in_units_of_length_match_the_exact_quotient_to_a_raw_unit() {
    let mut rng = Rng::new(11);
    let mut worst = 0i64;
    for _ in 0..200_000 {
        let metres = (10f64.powf(rng.uniform(-3.5, 3.5))) as f32;
        let per_metre = Reciprocal::of(metres);
        let base = (rng.uniform(-1e6, 1e6) * 10f64.powf(rng.uniform(-8.0, 0.0))) as f32;
        let offset = (rng.uniform(-250.0, 250.0)
            * f64::from(metres)
            * 10f64.powf(rng.uniform(-7.0, 0.0))) as f32;
        let to = (base + offset).clamp(-1e6, 1e6);
        let got = convert::offset(base, to, &per_metre);
        let exact = (f64::from(to) - f64::from(base)) / f64::from(metres) * 16384.0;
        if exact.abs() >= 2f64.powi(31) - 1.0 {
            continue;
        }
        worst = worst.max((i64::from(got) - exact.round() as i64).abs());
    }
    assert!(worst <= 1, "worst {worst} raw units");
}

/// Near the range's edge (2^31 raw units) the relative errors of the kept difference (2^-32)
/// and of the reciprocal (2^-31) reach a raw unit: the offset is within half a unit plus
/// 3 2^-32 of the exact quotient; the fuzzer's case is two units off the rounded quotient.
#[test]
fn offsets_at_the_range_edge_stay_within_the_relative_bound() {
    let mut rng = Rng::new(12);
    let mut worst_excess = 0.0f64;
    for _ in 0..400_000 {
        let metres = rng.uniform(1.0, 10.0) as f32;
        let per_metre = Reciprocal::of(metres);
        let base = rng.uniform(-1e6, 1e6) as f32;
        let reach = f64::from(metres) * 2f64.powi(17) * rng.uniform(0.5, 0.999);
        let to = (f64::from(base) + reach * rng.uniform(-1.0, 1.0).signum()) as f32;
        if to.abs() > 1e6 {
            continue;
        }
        let got = f64::from(convert::offset(base, to, &per_metre));
        let exact = (f64::from(to) - f64::from(base)) / f64::from(metres) * 16384.0;
        if exact.abs() >= 2f64.powi(31) - 2.0 {
            continue;
        }
        let bound = 0.5 + 3.0 * exact.abs() / 2f64.powi(32);
        worst_excess = worst_excess.max((got - exact).abs() - bound);
    }
    assert!(worst_excess <= 0.0, "past the bound by {worst_excess}");
    let (base, to, metres) = (5.136_999_4e5_f32, 1.108_832_8e1_f32, 3.958_547_8_f32);
    let got = f64::from(convert::offset(base, to, &Reciprocal::of(metres)));
    let exact = (f64::from(to) - f64::from(base)) / f64::from(metres) * 16384.0;
    assert_eq!((got - exact.round()).abs(), 2.0, "{got} against {exact}");
    assert!((got - exact).abs() <= 0.5 + 3.0 * exact.abs() / 2f64.powi(32));
}

#[test]
fn fixed_point_states_refuse_what_f32_states_refuse() {
    let limits = Limits::<Fixed>::new(2.0, 2.0, 1.0, 1.0).unwrap();
    let ok = [0.0, 0.0, 0.0];
    let cases = [
        ([f32::NAN, 0.0, 0.0], twocars::Error::NonFiniteInput),
        ([0.0, f32::INFINITY, 0.0], twocars::Error::NonFiniteInput),
        (
            [0.0, 0.0, f32::NEG_INFINITY],
            twocars::Error::NonFiniteInput,
        ),
        ([1.0e6f32.next_up(), 0.0, 0.0], twocars::Error::OutOfRange),
        ([0.0, 0.0, 1.0e4f32.next_up()], twocars::Error::OutOfRange),
        // 200 r_p = 100 m at w_pm = 2: just beyond.
        ([100.01, 0.0, 0.0], twocars::Error::OutOfRange),
    ];
    for (evader, status) in cases {
        assert_eq!(
            limits.states(ok, evader).map(|_| ()),
            Err(status),
            "{evader:?}"
        );
        let f = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).unwrap();
        if status == twocars::Error::NonFiniteInput {
            assert_eq!(f.states(ok, evader).map(|_| ()), Err(status));
        }
    }
    let (p, e) = limits
        .states([1.0e6, -1.0e6, 7.0], [1.0e6 - 3.0, -1.0e6, -7.0])
        .unwrap();
    assert_eq!((p.x.raw(), e.x.raw(), e.y.raw()), (0, -6 * 16384, 0));
    // Apart by 1e-5 r_p (beyond the capture radius) but below half a raw unit: refused.
    assert_eq!(
        limits.states(ok, [5.0e-6, 0.0, 0.0]).map(|_| ()),
        Err(twocars::Error::OutOfRange)
    );
}
