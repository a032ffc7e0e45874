//! The f32 backend's own functions against f64, over the law's envelope, with the bounds stated
//! in `src/num/f32_math.rs`.

use twocars::num::f32_math::{atan2, sin_cos, sqrt, wrap_signed};
use twocars::Scalar;
use twocars_sim::sim::angle_error;

/// Evenly spaced f32 samples of [lo, hi].
fn samples(lo: f32, hi: f32, n: usize) -> impl Iterator<Item = f32> {
    (0..=n).map(move |i| lo + (hi - lo) * (i as f32 / n as f32))
}

fn worst_sin_cos(lo: f32, hi: f32) -> f64 {
    samples(lo, hi, 400_000)
        .map(|x| {
            let (s, c) = sin_cos(x);
            let x64 = f64::from(x);
            (f64::from(s) - x64.sin())
                .abs()
                .max((f64::from(c) - x64.cos()).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn sin_cos_within_1e_7_over_the_envelope() {
    let near = worst_sin_cos(-7.0, 7.0);
    let far = worst_sin_cos(-1.0e4, 1.0e4);
    println!("sin_cos: worst absolute error {near:.2e} on [-7, 7], {far:.2e} on [-1e4, 1e4]");
    assert!(near <= 1e-7, "{near}");
    assert!(far <= 1e-7, "{far}");
}

#[test]
fn atan2_within_3e_7_in_every_direction() {
    let mut worst: f64 = 0.0;
    for i in 0..200_000 {
        let angle = -std::f64::consts::PI + std::f64::consts::TAU * (i as f64 / 200_000.0);
        for r in [1e-3f64, 1.0, 7.0, 1e4] {
            let (x, y) = ((r * angle.cos()) as f32, (r * angle.sin()) as f32);
            let want = f64::from(y).atan2(f64::from(x));
            let got = f64::from(atan2(y, x));
            worst = worst.max(angle_error(got, want));
        }
    }
    println!("atan2: worst absolute error {worst:.2e} rad");
    assert!(worst <= 3e-7, "{worst}");
    assert_eq!(atan2(0.0, 0.0), 0.0);
    assert!((atan2(0.0, -1.0) - core::f32::consts::PI).abs() < 1e-7);
    assert_eq!(atan2(0.0, 1.0), 0.0);
}

#[test]
fn sqrt_is_within_one_ulp_and_zero_below_zero() {
    for x in samples(0.0, 1.0e6, 100_000).chain(samples(0.0, 1.0, 10_000)) {
        let want = f64::from(x).sqrt();
        let got = f64::from(sqrt(x));
        assert!(
            (got - want).abs() <= want * 1.2e-7 + 1e-30,
            "{x}: {got} vs {want}"
        );
    }
    assert_eq!(sqrt(-1.0), 0.0);
    assert_eq!(sqrt(f32::NAN), 0.0);
}

#[test]
fn wrap_signed_reduces_headings_to_within_pi_and_keeps_them_exact() {
    let mut worst: f64 = 0.0;
    for x in samples(-1.0e4, 1.0e4, 400_000) {
        let r = f64::from(wrap_signed(x));
        let pi = std::f64::consts::PI;
        assert!(r.abs() <= pi + 1e-6, "{x} -> {r}");
        // r = x - 2 pi k for an integer k, to within the error.
        let turns = (f64::from(x) - r) / std::f64::consts::TAU;
        worst = worst.max((turns - turns.round()).abs() * std::f64::consts::TAU);
    }
    println!("wrap_signed: worst absolute error {worst:.2e} rad on [-1e4, 1e4]");
    assert!(worst <= 3e-7, "{worst}");
}

/// `Scalar::wrap_positive` on f32 (micromath's reduction): [0, 2 pi), within 6e-7 rad of the
/// exact angle (the signed reduction's 3e-7, then a turn added in f32: 2 pi's own rounding,
/// 1.7e-7, and the sum's, up to 2.4e-7).
#[test]
fn wrap_positive_reduces_to_one_turn_and_keeps_angles_exact() {
    let mut worst: f64 = 0.0;
    for x in samples(-1.0e4, 1.0e4, 400_000).chain([-1.0e-30, -0.0, 0.0, 1.0e-30]) {
        let r = x.wrap_positive();
        assert!((0.0..std::f32::consts::TAU).contains(&r), "{x} -> {r}");
        worst = worst.max(angle_error(f64::from(r), f64::from(x)));
    }
    println!("wrap_positive: worst absolute error {worst:.2e} rad on [-1e4, 1e4]");
    assert!(worst <= 6e-7, "{worst}");
}
