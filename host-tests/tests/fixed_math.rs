//! The fixed-point backend's functions against f64 on exactly representable inputs, with the
//! bounds stated in `src/num/fixed/mod.rs`; its products exact; its invalid value from conversions and
//! divisions; overflow of `+`, `-` and `*` a panic in debug builds, as for Rust's integers.

use twocars::num::fixed::Fixed;
use twocars::Scalar;
use twocars_sim::sim::angle_error;

const LSB: f64 = 1.0 / 16384.0;

fn fixed(raw: i32) -> Fixed {
    Fixed::from_raw(raw)
}

#[test]
fn sin_cos_within_2e_4_for_headings_up_to_1e4_rad() {
    let mut worst: f64 = 0.0;
    // A stride up to 1e4 rad, and every value within a turn and a bit either side of 0 (where
    // the quarter turns are found by compares).
    let near = -120_000..=120_000;
    for raw in (-163_840_000..=163_840_000).step_by(997).chain(near) {
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
            worst = worst.max(angle_error(got, want));
        }
    }
    println!("fixed atan2: worst absolute error {worst:.2e} rad");
    assert!(worst <= 3e-4, "{worst}");
    assert_eq!(Fixed::atan2(fixed(0), fixed(0)), fixed(0));
}

#[test]
fn tangent_heading_within_the_atan2_bound_at_every_scale() {
    // Valid tangents (L^2 + k^2 = |D|^2) from 0.05 to 210 pursuer radii, the scale at which the
    // operands are shifted included; compared with the exact direction of the same raw inputs.
    // Powers of two (2, 4, 128 r_p: raw -2^15, -2^16, -2^21 on the axes at i = 0 and 500), where
    // the shift, taken from one's-complement magnitudes, leaves an operand at 2^15 itself.
    let mut worst: f64 = 0.0;
    for d in [0.05f64, 1.0, 1.9, 2.0, 2.1, 4.0, 10.0, 100.0, 128.0, 210.0] {
        for i in 0..2_000 {
            let angle = -std::f64::consts::PI + std::f64::consts::TAU * (f64::from(i) / 2_000.0);
            for k_over_d in [-0.999, -0.7, -0.2, 0.0, 0.3, 0.8, 0.999] {
                let raw = |v: f64| (v * 16_384.0).round() as i32;
                let (dx, dy) = (raw(d * angle.cos()), raw(d * angle.sin()));
                let k = raw(d * k_over_d);
                let length = raw(d * (1.0 - k_over_d * k_over_d).sqrt());
                let [l, k_f, dx_f, dy_f] = [length, k, dx, dy].map(f64::from);
                let want = (l * dy_f - k_f * dx_f).atan2(l * dx_f + k_f * dy_f);
                let got =
                    Fixed::tangent_heading(fixed(length), fixed(k), fixed(dx), fixed(dy)).to_f64();
                worst = worst.max(angle_error(got, want));
            }
        }
    }
    println!("fixed tangent_heading: worst absolute error {worst:.2e} rad");
    assert!(worst <= 3e-4, "{worst}");
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

/// floor(sqrt(n)) for any u64, exactly.
fn isqrt_u64(n: u64) -> u64 {
    let mut r = (n as f64).sqrt() as u64;
    while r * r > n {
        r -= 1;
    }
    while (r + 1) * (r + 1) <= n {
        r += 1;
    }
    r
}

/// The square root against its definition: raw shifted left by s = min(leading zeros, 14)
/// rounded down to even, its integer root, shifted left by (14 - s) / 2. The backend's Newton
/// steps land within one unit of that root (of its last place, 2^((14 - s) / 2)): every raw below
/// 2^24, a stride through the rest and the squares give that (0.5% of them one unit off).
#[test]
fn sqrt_is_within_one_unit_of_the_integer_root_of_the_shifted_raw_value() {
    let stride = (1u32 << 24..i32::MAX as u32).step_by(4_099);
    let squares = (1u32..46_341).flat_map(|r| [r * r - 1, r * r, r * r + 1]);
    let (mut checked, mut off) = (0u32, 0u32);
    for raw in (1u32..1 << 24).chain(stride).chain(squares) {
        let shift = raw.leading_zeros().min(14) & !1;
        let unit = 1i64 << ((14 - shift) / 2);
        let want = (isqrt_u64(u64::from(raw) << shift) << ((14 - shift) / 2)) as i64;
        let got = i64::from(fixed(raw as i32).sqrt().raw());
        assert!((got - want).abs() <= unit, "raw {raw}: {got} vs {want}");
        checked += 1;
        off += u32::from(got != want);
    }
    println!("fixed sqrt: {off} of {checked} roots one unit off the integer root");
}

/// The arc test's `between` (one sign test of two differences) is `low <= x <= high`, at the
/// bounds and across the law's angles.
#[test]
fn between_is_low_at_most_x_at_most_high() {
    let (tau, resolution) = (Fixed::tau().raw(), Fixed::from_f32(1.0e-3).raw());
    for (low, high) in [
        (resolution, tau - resolution),
        (resolution, resolution),
        (5, -5),
    ] {
        for x in (-2 * tau..=2 * tau)
            .step_by(7)
            .chain([low - 1, low, high, high + 1])
        {
            assert_eq!(
                fixed(x).between(fixed(low), fixed(high)),
                low <= x && x <= high,
                "{low} <= {x} <= {high}"
            );
        }
    }
}

/// Headings reduce to [-pi, pi] by whole turns of the backend's 2 pi.
#[test]
fn wrap_signed_reduces_by_whole_turns_to_within_pi() {
    let (pi, tau) = (Fixed::pi().raw(), Fixed::tau().raw());
    let limit = (1.0e4 * 16_384.0) as i32;
    for raw in (-limit..=limit).step_by(97).chain(-2 * tau..=2 * tau) {
        let wrapped = fixed(raw).wrap_signed().raw();
        assert!((-pi..=pi).contains(&wrapped), "{raw} -> {wrapped}");
        assert_eq!((raw - wrapped) % tau, 0, "{raw} -> {wrapped}");
    }
}

/// Whether `f` panics (quietly: the expected panics are not printed).
#[cfg(debug_assertions)]
fn panics<T>(f: impl FnOnce() -> T + std::panic::UnwindSafe) -> bool {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let panicked = std::panic::catch_unwind(f).is_err();
    std::panic::set_hook(hook);
    panicked
}

#[test]
fn conversions_and_divisions_out_of_range_give_the_invalid_value_which_propagates() {
    let one = Fixed::one();
    assert!(!Fixed::from_f32(1.0e6).is_valid(), "conversion beyond 2^17");
    assert!(!Fixed::from_f32(-1.0e6).is_valid());
    assert!(!Fixed::from_f32(f32::NAN).is_valid());
    assert!(!(one / Fixed::zero()).is_valid(), "division by zero");
    let big = Fixed::from_f32(100_000.0);
    assert!(
        !(big / Fixed::from_f32(0.5)).is_valid(),
        "quotient beyond 2^17"
    );
    let invalid = one / Fixed::zero();
    for v in [-invalid, one / invalid, invalid / one, invalid.sqrt()] {
        assert!(!v.is_valid());
    }
    let (s, c) = invalid.sin_cos();
    assert!(!s.is_valid() && !c.is_valid());
    assert!(!Fixed::atan2(invalid, one).is_valid());
    assert!(!Fixed::atan2(one, invalid).is_valid());
    assert!(invalid.to_f32().is_nan());
    // In range: exact.
    assert_eq!(
        (Fixed::from_f32(1.5) * Fixed::from_f32(-2.0)).to_f32(),
        -3.0
    );
    assert_eq!((Fixed::from_f32(3.0) / Fixed::from_f32(4.0)).to_f32(), 0.75);
}

/// `+`, `-` and `*` are not checked in release builds (the law's envelope bounds every
/// intermediate); in debug builds, which every host test and fuzz run uses, an overflow panics.
#[cfg(debug_assertions)]
#[test]
fn overflowing_sums_and_products_panic_in_debug_builds() {
    let big = Fixed::from_f32(100_000.0);
    assert!(panics(|| big + big), "sum beyond 2^17");
    assert!(panics(|| -big - big), "difference beyond 2^17");
    assert!(panics(|| big * Fixed::from_f32(2.0)), "product beyond 2^17");
    assert!(panics(|| big * big));
    assert!(panics(|| big * -big));
    assert!(!panics(|| big + (-big)));
    assert!(!panics(|| Fixed::from_f32(360.0) * Fixed::from_f32(360.0)));
}

#[test]
fn products_and_products_by_small_factors_are_the_exact_product_rounded_half_up() {
    // Raw operands of every size and sign.
    let mut state = 0x2CA5_2019_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let bits = (state >> 33) as u32 as i32;
        bits >> ((state >> 8) % 31)
    };
    // The law's operand sizes: 2^14 (1), 2^17 (8), 2^21 (128), 2^27 (8192), either sign.
    let edges = [1 << 14, 1 << 17, 1 << 21, 1 << 27].map(|e: i32| [e - 1, e, -e, 1 - e]);
    let edges: Vec<i32> = edges.into_iter().flatten().collect();
    let pairs = edges
        .iter()
        .flat_map(|&a| edges.iter().map(move |&b| (a, b)));
    let (mut checked, mut small, mut nonnegative) = (0, 0, 0);
    for (a, b) in (0..400_000).map(|_| (next(), next())).chain(pairs) {
        let exact = (i64::from(a) * i64::from(b) + (1 << 13)) >> 14;
        // Products that fit, short of the last 2^-7 of the range (the law's stay below 9.0e4,
        // 0.69 of it), where a partial sum may overflow first.
        let Ok(raw) = i32::try_from(exact) else {
            continue;
        };
        if raw.unsigned_abs() >= (1 << 31) - (1 << 24) {
            continue;
        }
        assert_eq!(fixed(a) * fixed(b), fixed(raw), "{a} * {b}");
        checked += 1;
        // The two-product form for a factor below 8 gives the same rounded product.
        if b.unsigned_abs() < 1 << 17 {
            assert_eq!(
                fixed(a).mul_small(fixed(b)),
                fixed(raw),
                "{a} mul_small {b}"
            );
            small += 1;
        }
        // And the form for a factor in [0, 16], its low product unsigned.
        if (0..=1 << 18).contains(&b) {
            assert_eq!(
                fixed(a).mul_nonnegative(fixed(b)),
                fixed(raw),
                "{a} mul_nonnegative {b}"
            );
            nonnegative += 1;
        }
    }
    assert!(
        checked > 100_000 && small > 50_000 && nonnegative > 25_000,
        "{checked} {small} {nonnegative}"
    );
}

/// The normalised backend's units make the pursuer's limits exactly one (the law skips its
/// products by them), and one unit of curvature, the pursuer's full turn, is within the true
/// w_pm: the unit of length is 1 / w_pm rounded up, never down.
#[test]
fn the_pursuer_is_the_unit_and_its_full_curvature_stays_within_w_pm() {
    let mut rounded_up = 0;
    for i in 0..20_000u32 {
        // w_pm from 2e-4 to 1e4 1/m, spaced geometrically, and every f32 near a few round values.
        let w_pm = if i < 19_000 {
            2.0e-4_f32 * 5.0e7_f32.powf(i as f32 / 19_000.0)
        } else {
            f32::from_bits(3.0_f32.to_bits() - 500 + (i - 19_000))
        };
        let Ok(limits) = twocars::Limits::<Fixed>::new(2.0, w_pm, 1.0, w_pm / 2.0) else {
            continue;
        };
        let p = &limits.pursuer;
        assert_eq!(
            [p.w_max(), p.radius(), p.v_max(), p.seconds_per_radian()],
            [Fixed::one(); 4],
            "{w_pm}"
        );
        let full = limits.units.curvature(Fixed::one());
        assert!(full <= f64::from(w_pm), "{w_pm}: {full}");
        assert!(full >= f64::from(w_pm) * (1.0 - 1.2e-7), "{w_pm}: {full}");
        assert!((full as f32) <= w_pm);
        if f64::from(1.0 / w_pm) * f64::from(w_pm) < 1.0 {
            rounded_up += 1;
        }
    }
    // The rounding up is exercised, not only exact reciprocals.
    assert!(rounded_up > 1000, "{rounded_up}");
}

/// The fixed-point law's headings, reduced from f32 radians when its states are made
/// (`Limits::states`), are within half a raw unit (2^-15 rad) and the f32 reduction's 3e-7 rad
/// of the exact angle, at every size the envelope allows (|theta| <= 1e4 rad).
#[test]
fn states_reduce_headings_to_within_half_a_raw_unit() {
    let limits = twocars::Limits::<Fixed>::new(2.0, 2.0, 1.0, 1.0).expect("paper limits");
    let mut worst = 0.0f64;
    for i in 0..19_999 {
        let theta = -9_999.0_f32 + i as f32 + 0.123 * (i % 7) as f32;
        let (pursuer, _) = limits
            .states([0.0, 0.0, theta], [3.0, 4.0, 0.0])
            .expect("in the envelope");
        let error = angle_error(pursuer.theta.to_f64(), f64::from(theta));
        worst = worst.max(error);
    }
    println!("fixed heading reduction: worst {worst:.2e} rad");
    assert!(worst <= 1.0 / 32_768.0 + 3.0e-7, "{worst:e}");
}
