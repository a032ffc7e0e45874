//! IEEE 754 binary32 to and from fixed point with integer operations only: the wire's `f32`
//! values on cores without an FPU (Cortex-M0/M0+), where every `f32` operation is a call into
//! the soft-float library.
//!
//! Every conversion here rounds to nearest from the exact value of its operands (ties away from
//! zero into fixed point, ties to even into `f32`, as IEEE 754 does), so it is the same on every
//! core and equal to the exact value rounded once. Tested exhaustively over every exponent, both
//! signs, subnormals, NaN and the infinities (`host-tests/tests/ieee.rs`).

/// A finite `f32` taken apart: its value is `(-1)^negative * mantissa * 2^exponent`, with
/// `mantissa < 2^24` (the hidden bit included; 0 for zero).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parts {
    /// The sign bit.
    pub negative: bool,
    /// The significand as an integer, below 2^24.
    pub mantissa: u32,
    /// The power of two it is scaled by, in [-149, 104].
    pub exponent: i32,
}

/// Bits of the largest finite magnitude's exponent field (all ones is NaN or infinity).
const EXPONENT_MASK: u32 = 0x7f80_0000;
const MANTISSA_MASK: u32 = 0x007f_ffff;
const SIGN: u32 = 0x8000_0000;

/// Whether the `f32` with these bits is finite (not NaN, not an infinity).
#[inline(always)]
pub fn is_finite_bits(bits: u32) -> bool {
    bits & EXPONENT_MASK != EXPONENT_MASK
}

/// The magnitude's bits: an order-preserving integer for finite values (|a| <= |b| exactly when
/// `magnitude_bits(a) <= magnitude_bits(b)`), so envelopes compare without float operations.
#[inline(always)]
pub fn magnitude_bits(bits: u32) -> u32 {
    bits & !SIGN
}

/// The parts of a finite `f32`; `None` for NaN and the infinities.
#[inline(always)]
pub fn parts(bits: u32) -> Option<Parts> {
    if !is_finite_bits(bits) {
        return None;
    }
    let field = (bits & EXPONENT_MASK) >> 23;
    let fraction = bits & MANTISSA_MASK;
    let (mantissa, exponent) = if field == 0 {
        (fraction, -149)
    } else {
        (fraction | 1 << 23, field as i32 - 150)
    };
    Some(Parts {
        negative: bits & SIGN != 0,
        mantissa,
        exponent,
    })
}

/// `value >> shift` rounded to nearest, ties away from zero; 0 for shifts of 64 and more. (64-bit
/// operations only: on a Cortex-M0 each 128-bit one is a chain of library calls.)
#[inline(always)]
pub fn shift_round(value: u64, shift: u32) -> u64 {
    match shift {
        0 => value,
        1..=63 => (value >> shift) + (value >> (shift - 1) & 1),
        _ => 0,
    }
}

/// The finite `f32` times 2^`scale_bits` rounded to nearest (ties away from zero) as an integer;
/// `None` for NaN, the infinities and magnitudes of 2^`limit_bits` or more after rounding.
/// `limit_bits` <= 62.
#[inline(always)]
pub fn to_fixed(bits: u32, scale_bits: i32, limit_bits: u32) -> Option<i64> {
    let p = parts(bits)?;
    let shift = p.exponent + scale_bits;
    let mantissa = u64::from(p.mantissa);
    let magnitude = if shift >= 0 {
        // At or beyond 2^limit_bits (a mantissa is at least 1), or beyond 64 bits.
        let shift = shift.unsigned_abs();
        if mantissa != 0 && (shift >= limit_bits || mantissa.leading_zeros() < shift) {
            return None;
        }
        mantissa << shift
    } else {
        shift_round(mantissa, shift.unsigned_abs())
    };
    if magnitude >> limit_bits != 0 {
        return None;
    }
    let magnitude = magnitude as i64;
    Some(if p.negative { -magnitude } else { magnitude })
}

/// The `f32` nearest to `(-1)^negative * magnitude * 2^exponent` (ties to even), overflow to
/// the infinity of its sign, underflow to a subnormal or a signed zero, as IEEE 754 rounds an
/// exact result once.
pub fn f32_from_scaled(negative: bool, magnitude: u64, exponent: i32) -> f32 {
    let sign = if negative { SIGN } else { 0 };
    if magnitude == 0 {
        return f32::from_bits(sign);
    }
    // The binade: magnitude * 2^exponent in [2^e, 2^(e+1)).
    let top = 63 - magnitude.leading_zeros() as i32;
    let e = top + exponent;
    // Keep 24 significant bits, or fewer below the normal range (e < -126).
    let keep = if e < -126 { 24 - (-126 - e) } else { 24 };
    let drop = top + 1 - keep;
    let mantissa: u64 = if drop <= 0 {
        magnitude << (-drop).clamp(0, 63)
    } else if drop >= 64 {
        0
    } else {
        let drop = drop as u32;
        let kept = magnitude >> drop;
        let rest = magnitude & ((1u64 << drop) - 1);
        let half = 1u64 << (drop - 1);
        let up = rest > half || (rest == half && kept & 1 == 1);
        kept + u64::from(up)
    };
    // The quantum of the kept mantissa's last bit.
    let quantum = exponent + drop;
    // mantissa * 2^quantum, with mantissa < 2^24 (or exactly 2^24 after rounding up).
    let (mantissa, quantum) = if mantissa >> 24 != 0 {
        (mantissa >> 1, quantum + 1)
    } else {
        (mantissa, quantum)
    };
    let mantissa = mantissa as u32;
    if mantissa == 0 {
        return f32::from_bits(sign);
    }
    // Normal: mantissa in [2^23, 2^24), field = quantum + 150; subnormal: quantum = -149.
    let field = if mantissa >> 23 != 0 {
        quantum + 150
    } else {
        0
    };
    if field >= 255 {
        return f32::from_bits(sign | EXPONENT_MASK);
    }
    f32::from_bits(sign | (field as u32) << 23 | (mantissa & MANTISSA_MASK))
}
