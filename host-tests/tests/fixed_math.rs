//! The fixed-point backend's functions against f64 on exactly representable inputs, with the
//! bounds stated in `src/num/fixed.rs`, and its arithmetic's refusal to wrap or saturate.

use twocars::num::fixed::Fixed;
use twocars::Scalar;

const LSB: f64 = 1.0 / 16384.0;

fn fixed(raw: i32) -> Fixed {
    Fixed::from_raw(raw)
}

#[test]
fn sin_cos_within_2e_4_for_headings_up_to_1e4_rad() {
    let mut worst: f64 = 0.0;
    for raw in (-163_840_000..=163_840_000).step_by(997) {
        let (s, c) = fixed(raw).sin_cos();
        let x = f64::from(raw) * LSB;
        worst = worst
            .max((s.to_f64() - x.sin()).abs())
            .max((c.to_f64() - x.cos()).abs());
    }
    println!("fixed sin_cos: worst absolute error {worst:.2e}");
    assert!(worst <= 2e-4, "{worst}");
}

#[test]
fn atan2_within_3e_4_rad_for_every_direction_and_magnitude() {
    let mut worst: f64 = 0.0;
    for i in 0..100_000 {
        let angle = -std::f64::consts::PI + std::f64::consts::TAU * (f64::from(i) / 100_000.0);
        for magnitude in [64.0f64, 16_384.0, 3.0e6, 2.0e9] {
            let (x, y) = (
                (magnitude * angle.cos()).round() as i32,
                (magnitude * angle.sin()).round() as i32,
            );
            let want = f64::from(y).atan2(f64::from(x));
            let got = Fixed::atan2(fixed(y), fixed(x)).to_f64();
            let mut err = (got - want).abs();
            if err > std::f64::consts::PI {
                err = std::f64::consts::TAU - err; // -pi vs pi
            }
            worst = worst.max(err);
        }
    }
    println!("fixed atan2: worst absolute error {worst:.2e} rad");
    assert!(worst <= 3e-4, "{worst}");
    assert_eq!(Fixed::atan2(fixed(0), fixed(0)), fixed(0));
}

#[test]
fn sqrt_within_one_lsb_plus_2_to_the_minus_15_relative() {
    let mut worst: f64 = 0.0;
    for raw in (1..i32::MAX).step_by(9_973).chain(1..20_000) {
        let want = (f64::from(raw) * LSB).sqrt();
        let got = fixed(raw).sqrt().to_f64();
        let bound = LSB + want / 32_768.0;
        assert!((got - want).abs() <= bound, "{raw}: {got} vs {want}");
        worst = worst.max((got - want).abs() / want);
    }
    println!("fixed sqrt: worst relative error {worst:.2e}");
    assert_eq!(fixed(-5).sqrt(), fixed(0));
}

#[test]
fn overflow_and_division_by_zero_give_the_invalid_value_which_propagates() {
    let big = Fixed::from_f32(100_000.0);
    let one = Fixed::one();
    assert!(!(big * big).is_valid(), "product beyond 2^17");
    assert!(!(big + big).is_valid(), "sum beyond 2^17");
    assert!(!(one / Fixed::zero()).is_valid(), "division by zero");
    assert!(!Fixed::from_f32(1.0e6).is_valid(), "conversion beyond 2^17");
    assert!(!Fixed::from_f32(f32::NAN).is_valid());
    let invalid = big * big;
    for v in [
        invalid + one,
        one - invalid,
        -invalid,
        invalid * one,
        one / invalid,
    ] {
        assert!(!v.is_valid());
    }
    assert!(invalid.to_f32().is_nan());
    assert!(!invalid.sqrt().is_valid());
    // In range: exact.
    assert_eq!(
        (Fixed::from_f32(1.5) * Fixed::from_f32(-2.0)).to_f32(),
        -3.0
    );
    assert_eq!((Fixed::from_f32(3.0) / Fixed::from_f32(4.0)).to_f32(), 0.75);
}

#[test]
fn products_are_the_exact_product_rounded_half_up_or_invalid() {
    // Raw operands of every size and sign, on both the 32-bit and the 64-bit path.
    let mut state = 0x2CA5_2019_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let bits = (state >> 33) as u32 as i32;
        bits >> ((state >> 8) % 31)
    };
    for _ in 0..200_000 {
        let (a, b) = (next(), next());
        if a == i32::MIN || b == i32::MIN {
            continue;
        }
        let exact = (i64::from(a) * i64::from(b) + (1 << 13)) >> 14;
        let got = fixed(a) * fixed(b);
        match i32::try_from(exact) {
            Ok(raw) if raw != i32::MIN => assert_eq!(got, fixed(raw), "{a} * {b}"),
            _ => assert!(!got.is_valid(), "{a} * {b} should overflow"),
        }
    }
}
