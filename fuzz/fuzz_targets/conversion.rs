//! The fixed-point backend's integer IEEE 754 conversions on arbitrary bit patterns: no panic
//! (overflow checks on); a value into Q17.14 is the exact value rounded once, or invalid where
//! none fits; a Q17.14 value times an f32 scale is the exact product rounded once; headings land
//! in [-pi, pi] within a raw unit of the f64 reduction; offsets within half a raw unit of the
//! exact quotient plus its 3 2^-32 (the difference's 2^-32 and the reciprocal's 2^-31, relative)
//! plus the positions' 2^-41 m each.
#![no_main]

use libfuzzer_sys::fuzz_target;
use twocars::num::convert::{self, Reciprocal};
use twocars::num::fixed::Fixed;
use twocars::Scalar;

fn word(data: &[u8], i: usize) -> u32 {
    let mut b = [0u8; 4];
    for (k, slot) in b.iter_mut().enumerate() {
        *slot = data.get(4 * i + k).copied().unwrap_or(0);
    }
    u32::from_le_bytes(b)
}

fuzz_target!(|data: &[u8]| {
    let (a, b, c) = (
        f32::from_bits(word(data, 0)),
        f32::from_bits(word(data, 1)),
        f32::from_bits(word(data, 2)),
    );
    // Into Q17.14.
    let got = Fixed::from_f32(a);
    let exact = (f64::from(a) * 16384.0).round();
    if a.is_finite() && exact.abs() < 2f64.powi(31) {
        assert_eq!(f64::from(got.raw()), exact, "{a:e}");
    } else {
        assert!(got.is_invalid(), "{a:e}");
    }
    // Back, scaled: |raw| < 2^29 keeps the f64 product exact.
    let raw = (word(data, 3) as i32) >> 3;
    let product = Fixed::from_raw(raw).to_f32_scaled(b);
    let want = (f64::from(raw) * f64::from(b) / 16384.0) as f32;
    assert!(
        product.to_bits() == want.to_bits() || (product.is_nan() && want.is_nan()),
        "{raw} x {b:e}"
    );
    // Headings.
    if a.is_finite() && a.abs() <= 1.0e4 {
        let h = i64::from(convert::heading(a));
        let pi = i64::from(Fixed::pi().raw());
        assert!((-pi..=pi).contains(&h));
        let tau = 2.0 * std::f64::consts::PI;
        let reduced = (f64::from(a) + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI;
        let d = (h - (reduced * 16384.0).round() as i64).abs();
        assert!(d <= 1 || (d - 2 * pi).abs() <= 1, "{a:e}: {h}");
    }
    // Offsets in a unit of length c.
    let envelope = |v: f32| v.is_finite() && v.abs() <= 1.0e6;
    if envelope(a) && envelope(b) && c.is_normal() && c > 1.0e-4 && c < 1.0e4 {
        let got = convert::offset(a, b, &Reciprocal::of(c));
        let exact = (f64::from(b) - f64::from(a)) / f64::from(c) * 16384.0;
        if exact.abs() < 2f64.powi(31) - 2.0 {
            let quantum = 2f64.powi(-40) / f64::from(c) * 16384.0;
            let bound = 0.5 + 3.0 * exact.abs() / 2f64.powi(32) + quantum;
            assert!(
                (f64::from(got) - exact).abs() <= bound,
                "{a:e} {b:e} / {c:e}"
            );
        }
    }
});
