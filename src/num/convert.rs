//! `f32` values (metres, radians) into the fixed-point law's normalised units, Q17.14 as raw
//! integers, and back, with integer operations only ([`super::ieee`]): no soft-float call
//! between a state's arrival and its command on a core without an FPU.
//!
//! - Positions: each coordinate exactly as an integer of 2^-40 m (|x| <= 1e6 m < 2^20 m), their
//!   difference exact (its top 32 bits kept, to 2^-32 relative), times the reciprocal of the unit
//!   of length ([`Reciprocal`], to 2^-31 relative), rounded once to Q17.14: within half a raw unit
//!   of the offset plus 3 2^-32 of it plus 2^-40 m, so one raw unit up to 2^29 raw units (2^15
//!   lengths) and two at the range's edge.
//! - Headings: reduced to [-pi, pi] as a binary angle (one turn = 2^32, the product of the exact
//!   `f32` by 2^32 / (2 pi) to 2^-38 relative), then to Q17.14 radians.
//! - Back to `f32`: a Q17.14 value times an `f32` scale, the exact product rounded once.

use super::ieee::{f32_from_scaled, parts, shift_round, to_fixed};

/// The fractional bits of the position integers, metres.
const POSITION_BITS: i32 = 40;
/// 2^40 / (2 pi), rounded: a binary angle (2^32 per turn) per radian, times 2^8.
const BINARY_ANGLE_PER_RADIAN_Q8: u64 = 174_992_710_548;
/// pi in Q29: Q14 radians per binary-angle unit, times 2^46 (pi / 2^17 = 2 pi / 2^32 * 2^14).
const PI_Q29: i64 = 1_686_629_713;

/// The reciprocal of a length (metres): `mantissa * 2^-shift` per metre, the mantissa in
/// (2^30, 2^31] (rounded to nearest: to 2^-31 relative); computed once per Configure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reciprocal {
    mantissa: u32,
    shift: i32,
}

impl Reciprocal {
    /// One metre per metre (the SI backends, which do not use it).
    pub const ONE: Reciprocal = Reciprocal {
        mantissa: 1 << 31,
        shift: 31,
    };

    /// The reciprocal of a positive, finite, normal `length` (metres); `ONE` otherwise.
    pub fn of(length: f32) -> Self {
        match parts(length.to_bits()) {
            Some(p) if !p.negative && p.mantissa >> 23 != 0 => {
                // 1 / (m 2^e) = (2^54 / m) 2^(-54 - e), rounded to nearest: m >= 2^23, so the
                // quotient is at most 2^31.
                let m = u64::from(p.mantissa);
                let quotient = ((1u64 << 54) + m / 2).checked_div(m).unwrap_or(1 << 31);
                Reciprocal {
                    mantissa: quotient as u32,
                    shift: 54 + p.exponent,
                }
            }
            _ => Reciprocal::ONE,
        }
    }
}

/// The offset `to - from` (metres, finite, within 1e6) in units of the length whose reciprocal
/// is `per_metre`, rounded to nearest with `fraction_bits` fractional bits; `None` if its
/// magnitude reaches 2^`limit_bits`.
fn scaled_offset(
    from: f32,
    to: f32,
    per_metre: &Reciprocal,
    fraction_bits: i32,
    limit_bits: u32,
) -> Option<i64> {
    let from = to_fixed(from.to_bits(), POSITION_BITS, 61)?;
    let to = to_fixed(to.to_bits(), POSITION_BITS, 61)?;
    let difference = to - from;
    // The difference's top 32 significant bits (to 2^-32 relative, below the reciprocal's
    // 2^-31), so that the product by the 31-bit reciprocal fits 64 bits.
    let exact = difference.unsigned_abs();
    let dropped = 32u32.saturating_sub(exact.leading_zeros());
    let product = shift_round(exact, dropped) * u64::from(per_metre.mantissa);
    // difference 2^-40 m times mantissa 2^-shift per metre, in units of 2^-fraction_bits.
    let shift = POSITION_BITS + per_metre.shift - fraction_bits - dropped as i32;
    let magnitude = if shift >= 0 {
        shift_round(product, shift.unsigned_abs())
    } else if product == 0 {
        0
    } else {
        return None;
    };
    if magnitude >> limit_bits != 0 {
        return None;
    }
    let magnitude = magnitude as i64;
    Some(if difference < 0 {
        -magnitude
    } else {
        magnitude
    })
}

/// The offset `to - from` (metres, finite, within the f32 envelope) in the law's units of
/// length, Q17.14 raw; `i32::MIN` (invalid) where it does not fit in 2^17.
pub fn offset(from: f32, to: f32, per_metre: &Reciprocal) -> i32 {
    match scaled_offset(from, to, per_metre, 14, 31) {
        Some(raw) => raw as i32,
        None => i32::MIN,
    }
}

/// Whether the offset (from, to) on both axes is longer than `radius` units of length (Q30, to
/// resolve what Q17.14 rounds to zero); only asked where both offsets round to zero.
pub fn apart_beyond(x: (f32, f32), y: (f32, f32), per_metre: &Reciprocal, radius: f32) -> bool {
    let fine = |(from, to): (f32, f32)| scaled_offset(from, to, per_metre, 30, 31);
    let radius = to_fixed(radius.to_bits(), 30, 31);
    match (fine(x), fine(y), radius) {
        (Some(dx), Some(dy), Some(r)) => dx * dx + dy * dy > r * r,
        // Beyond 2^1 units on an axis: apart.
        _ => true,
    }
}

/// A finite heading (radians) reduced to [-pi, pi], Q17.14 raw; `i32::MIN` (invalid) for
/// another.
pub fn heading(theta: f32) -> i32 {
    let Some(p) = parts(theta.to_bits()) else {
        return i32::MIN;
    };
    // theta 2^32 / (2 pi) = mantissa C 2^(exponent - 8), C = 2^40 / (2 pi) (38 bits: the
    // product fits 64), modulo 2^32.
    let product = u64::from(p.mantissa) * BINARY_ANGLE_PER_RADIAN_Q8;
    let left = p.exponent - 8;
    let turns = if left >= 32 {
        // Whole multiples of 2^32: zero modulo 2^32.
        0
    } else if left >= 0 {
        // Bits above 2^32 are whole turns: the wrapping shift drops only those.
        (product << left) as u32
    } else {
        shift_round(product, left.unsigned_abs()) as u32
    };
    let turns = if p.negative {
        turns.wrapping_neg()
    } else {
        turns
    };
    // Signed binary angle times pi / 2^17, rounded half away from zero.
    let product = i64::from(turns as i32) * PI_Q29;
    let half = 1i64 << 45;
    let raw = if product < 0 {
        -((-product + half) >> 46)
    } else {
        (product + half) >> 46
    };
    raw as i32
}

/// `raw / 2^14 * scale` as the `f32` nearest to the exact product (`i32::MIN`, invalid: NaN).
pub fn scaled_to_f32(raw: i32, scale: f32) -> f32 {
    if raw == i32::MIN {
        return f32::NAN;
    }
    match parts(scale.to_bits()) {
        Some(p) => {
            // Below 2^31 x 2^24: exact in 64 bits; the sign as IEEE 754 gives it (-0 included).
            let product = u64::from(raw.unsigned_abs()) * u64::from(p.mantissa);
            f32_from_scaled((raw < 0) != p.negative, product, p.exponent - 14)
        }
        // An infinite scale: the infinity of the product's sign, NaN for zero; NaN stays NaN.
        None if scale.to_bits() << 9 == 0 && raw != 0 => {
            let sign = if raw < 0 { 1u32 << 31 } else { 0 };
            f32::from_bits(scale.to_bits() ^ sign)
        }
        None => f32::NAN,
    }
}
