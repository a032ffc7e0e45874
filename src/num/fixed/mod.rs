//! The fixed-point backend for Cortex-M cores without an FPU (M0/M0+): Q17.14 numbers in an `i32`.
//!
//! The law runs *normalised* on this backend ([`Scalar::NORMALISED`]): lengths in units of the
//! pursuer's turning radius r_p, times in units of r_p / v_pm, positions relative to the pursuer
//! (see [`crate::Limits::states`]). One representation then covers every vehicle scale. Its
//! envelope (checked on input, `out_of_range` outside):
//! - the evader within 200 r_p of the pursuer on each axis;
//! - r_e / r_p = w_pm / w_em <= 16 and 1/16 <= v_em / v_pm <= 15/16;
//!
//! inside it every intermediate of the law stays below 2^17 in magnitude: the largest are
//! |D|^2 <= 9.0e4 and capture times within +-2.6e4 (the bounds, term by term, are in
//! `docs/numeric.md`), and [`crate::Guidance::new`] refuses a control period whose terms would
//! leave it ([`Scalar::MAX_PERIOD_TERM`]). So `+`, `-` and `*` are not checked at run time: like
//! Rust's integers they panic on overflow in debug builds (every host test and fuzz run) and wrap
//! in release builds, where the envelope keeps them from overflowing. Conversions and divisions
//! are checked: a result out of range, or a division by zero, gives the *invalid* value, which the
//! validated constructors ([`crate::Limits::new`], [`crate::Guidance::new`]) refuse, so it never
//! reaches the law's arithmetic.
//!
//! Resolution 2^-14 = 6.1e-5 (r_p, radians, r_p / v_pm). Error bounds, checked against f64 by
//! `cargo test -p host-tests --test fixed_math`:
//! - [`Scalar::sin_cos`]: absolute error <= 2e-4 (the angle as a binary angle, one turn = 2^32,
//!   so that a wrapping product reduces it; a quarter-wave table of 128 steps interpolated);
//! - [`Scalar::atan2`]: absolute error <= 3e-4 rad (octant reduction, the ratio to within two
//!   units of 2^-15, atan interpolated in a table of 64 steps, within 4.8e-5 rad on [0, 1]);
//! - [`Scalar::tangent_heading`]: absolute error <= 3e-4 rad (the operands scaled alike to 16
//!   bits, then [`Scalar::atan2`]);
//! - [`Scalar::sqrt`]: error <= 2^-14 + 2^-15 relative (the integer square root of the value
//!   shifted into 32 bits, to within one, by a Newton step from a table interpolated).

use core::ops::{Add, Div, Mul, Neg, Sub};

use super::convert::{self, Reciprocal};
use super::{ieee, Scalar};
use crate::error::Error;

/// Fractional bits.
const FRAC: u32 = 14;
/// 1.0 in Q14.
const ONE: i32 = 1 << FRAC;
/// The invalid value: a conversion out of range, or an overflowing or zero division. Negation,
/// division, square root, sine, cosine and atan2 propagate it.
const INVALID: i32 = i32::MIN;
/// pi and 2 pi in Q14.
const PI_Q14: i32 = 51_472;
const TAU_Q14: i32 = 102_944;
/// pi / 2 and pi in Q15 (the internal precision of `atan2`).
const FRAC_PI_2_Q15: i32 = 51_472;
const PI_Q15: i32 = 102_944;

/// A Q17.14 fixed-point number: `raw / 2^14`, or invalid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Default)]
pub struct Fixed(i32);

impl Fixed {
    /// The number `raw / 2^14`; `i32::MIN` is the invalid value.
    pub const fn from_raw(raw: i32) -> Self {
        Fixed(raw)
    }

    /// The raw Q17.14 integer.
    pub const fn raw(self) -> i32 {
        self.0
    }

    /// Whether this is the invalid value (an overflow or a division by zero upstream).
    pub const fn is_invalid(self) -> bool {
        self.0 == INVALID
    }

    fn from_wide(v: i64) -> Self {
        match i32::try_from(v) {
            Ok(raw) => Fixed(raw),
            Err(_) => Fixed(INVALID),
        }
    }
}

impl Add for Fixed {
    type Output = Fixed;
    #[inline]
    fn add(self, rhs: Fixed) -> Fixed {
        // Unchecked in release builds: the law's envelope bounds every sum (module docs); debug
        // builds (the host tests, the fuzzers) panic on overflow.
        Fixed(self.0 + rhs.0)
    }
}

impl Sub for Fixed {
    type Output = Fixed;
    #[inline]
    fn sub(self, rhs: Fixed) -> Fixed {
        Fixed(self.0 - rhs.0)
    }
}

impl Neg for Fixed {
    type Output = Fixed;
    #[inline]
    fn neg(self) -> Fixed {
        // -i32::MIN does not exist: the invalid value stays invalid.
        Fixed(self.0.wrapping_neg())
    }
}

impl Mul for Fixed {
    type Output = Fixed;
    #[inline]
    fn mul(self, rhs: Fixed) -> Fixed {
        // Four 32-bit products (one MULS each on a Cortex-M0, where a 64-bit product is a library
        // call). With a = h_a 2^14 + l_a (h_a = a >> 14, l_a = a mod 2^14 in [0, 2^14)) and b
        // alike, a b / 2^14 = h_a h_b 2^14 + h_a l_b + l_a h_b + l_a l_b / 2^14, rounded half up;
        // each partial product fits 32 bits whenever the result does. Unchecked in release
        // builds like `Add`; debug builds panic on overflow.
        let (a, b) = (self.0, rhs.0);
        let (a_high, a_low) = (a >> FRAC, a & (ONE - 1));
        let (b_high, b_low) = (b >> FRAC, b & (ONE - 1));
        let low = (a_low * b_low + (1 << (FRAC - 1))) >> FRAC;
        Fixed(a_high * b_high * ONE + a_high * b_low + a_low * b_high + low)
    }
}

impl Div for Fixed {
    type Output = Fixed;
    #[inline]
    fn div(self, rhs: Fixed) -> Fixed {
        if self.is_invalid() || rhs.is_invalid() || rhs.0 == 0 {
            return Fixed(INVALID);
        }
        // A dividend below 2^17 in magnitude shifts within 32 bits: a 32-bit division.
        if self.0.unsigned_abs() < 1 << 17 {
            return Fixed((self.0 << FRAC).checked_div(rhs.0).unwrap_or(INVALID));
        }
        // The dividend fits 46 bits; i64 division cannot overflow for a non-zero divisor.
        let quotient = (i64::from(self.0) << FRAC).checked_div(i64::from(rhs.0));
        quotient.map_or(Fixed(INVALID), Fixed::from_wide)
    }
}

/// sin(i pi / 256) in Q15 for i = 0..=128, rounded: a quarter wave in 128 steps, which
/// [`quarter_sine`] interpolates.
const SINE_Q15: [u16; 129] = [
    0, 402, 804, 1206, 1608, 2009, 2411, 2811, 3212, 3612, 4011, 4410, 4808, 5205, 5602, 5998,
    6393, 6787, 7180, 7571, 7962, 8351, 8740, 9127, 9512, 9896, 10_279, 10_660, 11_039, 11_417,
    11_793, 12_167, 12_540, 12_910, 13_279, 13_646, 14_010, 14_373, 14_733, 15_091, 15_447, 15_800,
    16_151, 16_500, 16_846, 17_190, 17_531, 17_869, 18_205, 18_538, 18_868, 19_195, 19_520, 19_841,
    20_160, 20_475, 20_788, 21_097, 21_403, 21_706, 22_006, 22_302, 22_595, 22_884, 23_170, 23_453,
    23_732, 24_008, 24_279, 24_548, 24_812, 25_073, 25_330, 25_583, 25_833, 26_078, 26_320, 26_557,
    26_791, 27_020, 27_246, 27_467, 27_684, 27_897, 28_106, 28_311, 28_511, 28_707, 28_899, 29_086,
    29_269, 29_448, 29_622, 29_792, 29_957, 30_118, 30_274, 30_425, 30_572, 30_715, 30_853, 30_986,
    31_114, 31_238, 31_357, 31_471, 31_581, 31_686, 31_786, 31_881, 31_972, 32_058, 32_138, 32_214,
    32_286, 32_352, 32_413, 32_470, 32_522, 32_568, 32_610, 32_647, 32_679, 32_706, 32_729, 32_746,
    32_758, 32_766, 32_768,
];

/// One raw unit of angle, 2^-14 rad, in binary-angle units (one turn = 2^32): 2^18 / (2 pi) =
/// 41,721.513, its integer part and its fraction in Q15.
const BINARY_ANGLE_PER_RAW: u32 = 41_721;
const BINARY_ANGLE_PER_RAW_FRAC_Q15: u32 = 16_823;

/// The angle `raw` / 2^14 rad as a binary angle, turns times 2^32 modulo one turn: the wrapping
/// product is the reduction, exact but for the constant's rounding (2^-16 units per raw unit,
/// 4.8e-5 rad at the largest raw value). With raw = h 2^15 + l (l in [0, 2^15)), the fraction's
/// product raw f / 2^15 is h f + l f / 2^15, each in 32 bits.
fn binary_angle(raw: i32) -> u32 {
    let high = (raw >> 15) as u32;
    let low = raw as u32 & 0x7FFF;
    (raw as u32)
        .wrapping_mul(BINARY_ANGLE_PER_RAW)
        .wrapping_add(high.wrapping_mul(BINARY_ANGLE_PER_RAW_FRAC_Q15))
        .wrapping_add((low * BINARY_ANGLE_PER_RAW_FRAC_Q15 + (1 << 14)) >> 15)
}

/// The sine of `position` / 2^30 quarter turns (`position` < 2^30) in raw Q14: [`SINE_Q15`]
/// interpolated linearly with a 16-bit fraction and rounded once (within 1.9e-5 of the sine
/// between entries, the entries within 1.5e-5, the rounding 3.1e-5). Inlined: its callers' masks
/// bound the index.
#[inline(always)]
fn quarter_sine(position: u32) -> i32 {
    let i = (position >> 23) as usize;
    let fraction = (position >> 7) & 0xFFFF;
    let (a, b) = (u32::from(SINE_Q15[i]), u32::from(SINE_Q15[i + 1]));
    // The sine rises over the quarter: b >= a, and a 2^16 + (b - a) 2^16 + 2^16 < 2^32.
    (((a << 16) + (b - a) * fraction + (1 << 16)) >> 17) as i32
}

/// Q15 to Q14, rounded.
fn q15_to_q14(v: i32) -> i32 {
    (v + 1) >> 1
}

/// atan(i / 64) in Q15 for i = 0..=64, rounded, and the last once more, so that the interpolation
/// at t = 1 reads within the table.
const ATAN_Q15: [u16; 66] = [
    0, 512, 1024, 1535, 2045, 2555, 3063, 3570, 4075, 4578, 5079, 5578, 6073, 6567, 7057, 7544,
    8027, 8508, 8984, 9456, 9925, 10389, 10849, 11305, 11756, 12203, 12645, 13082, 13514, 13941,
    14363, 14781, 15193, 15600, 16002, 16398, 16790, 17176, 17557, 17933, 18304, 18670, 19030,
    19386, 19736, 20081, 20421, 20756, 21086, 21411, 21732, 22047, 22358, 22664, 22966, 23262,
    23555, 23842, 24126, 24405, 24679, 24950, 25216, 25478, 25736, 25736,
];

/// atan(t) for t in [0, 1], t and the result in Q15: linear interpolation in a table of 64
/// steps, within 4.8e-5 rad (the second derivative's bound h^2 / 8 max|atan''| = 2.0e-5 plus
/// the roundings); one product where a polynomial takes five.
fn atan_unit_q15(t: u32) -> i32 {
    let t = t.min(1 << 15);
    let i = (t >> 9) as usize;
    let (a, b) = (i32::from(ATAN_Q15[i]), i32::from(ATAN_Q15[i + 1]));
    a + (((b - a) * (t & 511) as i32 + 256) >> 9)
}

/// The angle of the raw vector (x, y), raw Q14 radians in (-pi, pi]; 0 for the zero vector: the
/// octant's angle from the ratio of the smaller component to the larger.
#[inline(always)]
fn angle_of(y: i32, x: i32) -> i32 {
    let (ax, ay) = (x.unsigned_abs(), y.unsigned_abs());
    if ax == 0 && ay == 0 {
        return 0;
    }
    let (low, high) = if ay <= ax { (ay, ax) } else { (ax, ay) };
    let atan = atan_unit_q15(ratio_q15(low, high));
    let a = if ay <= ax { atan } else { FRAC_PI_2_Q15 - atan };
    let a = if x < 0 { PI_Q15 - a } else { a };
    let a = q15_to_q14(a);
    if y < 0 {
        -a
    } else {
        a
    }
}

/// 2^23 / (128 + i + 0.5) for i = 0..=127, rounded: 2^31 / h at the middle of each 128th of
/// h in [2^15, 2^16), the start of [`ratio_q15`]'s Newton step (within 1 / 514 of it).
const RECIPROCAL: [u16; 128] = [
    65_281, 64_777, 64_281, 63_792, 63_310, 62_836, 62_369, 61_909, 61_455, 61_008, 60_568, 60_133,
    59_705, 59_283, 58_867, 58_457, 58_053, 57_654, 57_260, 56_872, 56_489, 56_111, 55_738, 55_370,
    55_007, 54_649, 54_295, 53_946, 53_601, 53_261, 52_925, 52_593, 52_265, 51_942, 51_622, 51_306,
    50_995, 50_686, 50_382, 50_081, 49_784, 49_490, 49_200, 48_913, 48_630, 48_349, 48_072, 47_798,
    47_528, 47_260, 46_995, 46_733, 46_474, 46_218, 45_965, 45_714, 45_467, 45_222, 44_979, 44_739,
    44_502, 44_267, 44_035, 43_805, 43_577, 43_352, 43_129, 42_908, 42_690, 42_474, 42_260, 42_048,
    41_838, 41_631, 41_425, 41_222, 41_020, 40_820, 40_623, 40_427, 40_233, 40_041, 39_851, 39_662,
    39_476, 39_291, 39_108, 38_926, 38_746, 38_568, 38_392, 38_217, 38_044, 37_872, 37_702, 37_533,
    37_366, 37_200, 37_036, 36_873, 36_712, 36_552, 36_393, 36_236, 36_080, 35_926, 35_772, 35_620,
    35_470, 35_320, 35_172, 35_026, 34_880, 34_735, 34_592, 34_450, 34_309, 34_169, 34_031, 33_893,
    33_757, 33_622, 33_487, 33_354, 33_222, 33_091, 32_961, 32_832,
];

/// The number of bits of each 6-bit number, 0 for 0.
const BIT_LENGTH: [u8; 64] = [
    0, 1, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5,
    6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6, 6,
];

/// The number of bits of `v` < 2^18 (0 for 0; beyond 2^18 a wrong count, never a panic): two
/// compares and a lookup in [`BIT_LENGTH`], as a count of leading zeros is a library call on a
/// Cortex-M0. (A table of 256 and one compare: 15 instructions an evaluation fewer for 168 B
/// more; of 16 and three compares: 9 more for 20 B less.)
#[inline(always)]
fn bit_length_18(v: u32) -> u32 {
    if v >= 1 << 12 {
        12 + u32::from(BIT_LENGTH[(v >> 12) as usize & 63])
    } else if v >= 1 << 6 {
        6 + u32::from(BIT_LENGTH[(v >> 6) as usize])
    } else {
        u32::from(BIT_LENGTH[v as usize])
    }
}

/// |v| for v >= 0, |v| - 1 for v < 0 (v XOR its sign): two instructions where `unsigned_abs`
/// takes four on a Cortex-M0. Its bit length is |v|'s but at -2^n, one less.
#[inline(always)]
fn ones_complement_magnitude(v: i32) -> u32 {
    (v ^ (v >> 31)) as u32
}

/// The smallest right shift that brings `m` below 2^`bits`, for m < 2^(bits + 18): the number
/// of bits of m / 2^`bits`.
#[inline(always)]
fn shift_below(m: u32, bits: u32) -> u32 {
    bit_length_18(m >> bits)
}

/// low 2^15 / high for 0 <= low <= high, high > 0 (its caller, `angle_of`, orders them; debug
/// builds panic otherwise): the ratio in Q15, within two units of the exact quotient (test
/// `ratio_is_within_two_units_of_the_quotient`) and at most 2^15. Both shifted alike so that
/// high is in [2^16, 2^17) (`shift_below`), then low times a reciprocal of high from a table
/// of 128 and one Newton step r (2 - h r) (multiplications only: the 32-bit division is a
/// library call of about 150 instructions).
pub(crate) fn ratio_q15(low: u32, high: u32) -> u32 {
    debug_assert!(low <= high && high > 0, "ratio_q15({low}, {high})");
    let (mut h, mut l) = (high, low);
    if h < 1 << 16 {
        (h, l) = (h << 16, l << 16);
    }
    // One running shift for both, applied once.
    let shift = shift_below(h, 17);
    (h, l) = (h >> shift, l >> shift);
    // r = 2^31 / (h / 2), within 1 / 514 from the table and within 2^-15 after one Newton step,
    // which never rises above 2^31 / (h / 2) (nor does its truncation); every product below 2^32.
    // half is in [2^15, 2^16), so its bits 8 to 14 are its 128th less 128: the mask is the index
    // (a shift pair on a Cortex-M0, where a bounded lookup took a subtraction, a compare and two
    // branches).
    let half = h >> 1;
    let mut r = u32::from(RECIPROCAL[(half >> 8) as usize & 127]);
    let error = 0u32.wrapping_sub(half * r);
    r = (r * (error >> 16)) >> 15;
    // (l / 2) r + 2^15 <= (h / 2) r + 2^15 <= 2^31 + 2^15; rounded. (The bound here lets the
    // compiler drop the caller's: `atan_unit_q15` reads the ratio's range across the call.)
    (((l >> 1) * r + (1 << 15)) >> 16).min(1 << 15)
}

/// 2^14 / sqrt(i / 64) for i = 16..=64, rounded: 1 / sqrt(X) in Q14 at each sixty-fourth of X
/// in [1/4, 1], which [`isqrt_normalised`] interpolates.
const RSQRT_Q14: [u16; 49] = [
    32768, 31790, 30894, 30070, 29309, 28602, 27945, 27330, 26755, 26214, 25705, 25225, 24770,
    24339, 23930, 23541, 23170, 22817, 22479, 22155, 21845, 21548, 21263, 20988, 20724, 20470,
    20225, 19988, 19760, 19539, 19326, 19119, 18919, 18725, 18536, 18354, 18176, 18004, 17837,
    17674, 17515, 17361, 17211, 17064, 16921, 16782, 16646, 16514, 16384,
];

/// The integer square root of m in [2^30, 2^32), to within one: y = 1 / sqrt(m / 2^32)
/// interpolated in a table (multiplications only: a division, and the bit-by-bit square root,
/// cost a hundred-odd instructions on a Cortex-M0), then the root m y / 2^32 and one Newton step
/// on the root. Over every m in [2^30, 2^32) (a throwaway exhaustive run) it is the largest root
/// whose square is at most m but for 2,576,063 values, one below, and 5, one above; never further.
/// (An exact correction by integer squares would cost 24 instructions a root.)
fn isqrt_normalised(m: u32) -> u32 {
    // X = m / 2^32 in Q16; y within 3.7e-4 relative (the interpolation's h^2 / 8 max |y''| at
    // X = 1/4, 7.3e-4 of y = 2), so the root below is within about a dozen units.
    let x = m >> 16;
    let i = ((m >> 26) as usize).saturating_sub(16);
    let fraction = (m >> 10) & 0xFFFF;
    let (a, b) = (u32::from(RSQRT_Q14[i]), u32::from(RSQRT_Q14[i + 1]));
    // y falls over the interval: a >= b, and (a - b) 2^16 < 2^26.
    let y = a - (((a - b) * fraction) >> 16);
    // sqrt(X) 2^16; then r += (m - r^2) / (2 r) with 1 / r = y / 2^30.
    let root = ((x * y) >> 14).min(0xFFFF);
    let residual = m.wrapping_sub(root * root) as i32;
    // |residual| < 2^22 (the root is within a dozen units): (residual / 2^6) y < 2^31.
    let step = ((residual >> 6) * y as i32) >> 25;
    root.wrapping_add_signed(step)
}

/// The raw Q14 square root of the positive raw value `a`. sqrt(a / 2^14) 2^14 = sqrt(a 2^14):
/// `a` shifted left by the even 2 h that brings it to [2^30, 2^32) (compares, not a count of
/// leading zeros: a library call on a Cortex-M0), and the root by 7 - h: root 2^7 / 2^h, floored
/// (within one of the integer root of a 2^14).
#[inline(never)]
fn sqrt_of_positive(a: u32) -> i32 {
    // One running shift (the compiler kept each step's test on the stack to redo the half shift;
    // the bit lengths' table, as in `shift_below`, measured no better here).
    let mut shift = 0;
    if a < 1 << 16 {
        shift = 16;
    }
    if a << shift < 1 << 24 {
        shift += 8;
    }
    if a << shift < 1 << 28 {
        shift += 4;
    }
    if a << shift < 1 << 30 {
        shift += 2;
    }
    // root <= 2^16, so root 2^7 <= 2^23: in range.
    let root = isqrt_normalised(a << shift);
    ((root << 7) >> (shift / 2)) as i32
}

impl Fixed {
    /// [`Scalar::wrap_signed`] of an angle beyond [-pi, pi], or the invalid value (itself).
    #[inline(never)]
    fn wrap_signed_beyond_pi(self) -> Self {
        if self.is_invalid() {
            return self;
        }
        let positive = self.wrap_positive();
        if positive.0 > PI_Q14 {
            Fixed(positive.0 - TAU_Q14)
        } else {
            positive
        }
    }
}

impl super::sealed::Sealed for Fixed {}

impl Scalar for Fixed {
    /// In units of the pursuer's turning radius, relative to the pursuer.
    const MAX_COORDINATE: f32 = 200.0;
    const MAX_HEADING: f32 = 1.0e4;
    /// 2^-14, 6.1e-5: the band is the larger magnitude's raw value shifted, rounded down, so it
    /// stays within the contract's 1e-4 at every magnitude (1e-4 itself is 1.6 raw units, which
    /// rounded to 2 made a band of 1.22e-4).
    const TIE_BAND: f32 = 1.0 / 16_384.0;
    // Angles carry ~3e-4 rad of error: an arc within 1e-3 of 0 or 2 pi is the tangent.
    const ARC_RESOLUTION: f32 = 1.0e-3;
    const NORMALISED: bool = true;
    const MAX_RADIUS_RATIO: f32 = 16.0;
    const MIN_SPEED_RATIO: f32 = 1.0 / 16.0;
    const MAX_SPEED_RATIO: f32 = 15.0 / 16.0;
    /// Half the range: with capture times within +-2.6e4, the near-field policy's comparison of
    /// a value less dt plus the tie floor stays below 2^17, as does 4 v_pm dt.
    const MAX_PERIOD_TERM: f32 = 32_768.0;

    /// Rounded to nearest (ties away from zero) from the exact `f32`, with integers only;
    /// invalid for NaN, the infinities and magnitudes from 2^17.
    #[inline(always)]
    fn from_f32(value: f32) -> Self {
        match ieee::to_fixed(value.to_bits(), FRAC as i32, 31) {
            Some(raw) => Fixed(raw as i32),
            None => Fixed(INVALID),
        }
    }
    #[inline]
    fn from_f32_toward_zero(value: f32) -> Self {
        let scaled = value * ONE as f32;
        if scaled.is_nan() || scaled.abs() >= 2_147_483_520.0 {
            return Fixed(INVALID);
        }
        // In range (checked above): the cast truncates toward zero.
        Fixed(scaled as i32)
    }
    fn to_f32(self) -> f32 {
        convert::scaled_to_f32(self.0, 1.0)
    }
    #[inline]
    fn to_f32_scaled(self, scale: f32) -> f32 {
        convert::scaled_to_f32(self.0, scale)
    }
    fn relative_position(
        x: (f32, f32),
        y: (f32, f32),
        _metres: f32,
        per_metre: &Reciprocal,
        radius: f32,
    ) -> Result<(Self, Self), Error> {
        let (dx, dy) = (
            Fixed(convert::offset(x.0, x.1, per_metre)),
            Fixed(convert::offset(y.0, y.1, per_metre)),
        );
        if dx.is_invalid() || dy.is_invalid() {
            return Err(Error::OutOfRange);
        }
        if dx.0 == 0 && dy.0 == 0 && convert::apart_beyond(x, y, per_metre, radius) {
            return Err(Error::OutOfRange);
        }
        Ok((dx, dy))
    }
    #[inline]
    fn reduced_heading(theta: f32) -> Self {
        Fixed(convert::heading(theta))
    }
    fn to_f64(self) -> f64 {
        if self.is_invalid() {
            return f64::NAN;
        }
        f64::from(self.0) / f64::from(ONE)
    }
    fn is_valid(self) -> bool {
        !self.is_invalid()
    }
    fn pi() -> Self {
        Fixed(PI_Q14)
    }
    fn never() -> Self {
        // 2^16 time units: capture times stay within [-2.6e4, 6.5e3] (`docs/numeric.md`), so
        // `never` minus any of them, 9.2e4 at most, stays below 2^17.
        Fixed(1 << 30)
    }
    fn tau() -> Self {
        Fixed(TAU_Q14)
    }
    // a f / 2^14 = a_h f + a_l f / 2^14 (a_h = a >> 14, a_l = a mod 2^14), rounded half up: the
    // same as `Mul` (whose a_h b_h 2^14 + a_h b_l is a_h f here, and a_l b_h 2^14 + a_l b_l is
    // a_l f), in two products; a_l f < 2^31 for |f| < 2^17 raw.
    #[inline(always)]
    fn mul_small(self, factor: Self) -> Self {
        debug_assert!(
            factor.0.unsigned_abs() < 1 << 17,
            "mul_small factor {factor:?}"
        );
        let (a, f) = (self.0, factor.0);
        let (a_high, a_low) = (a >> FRAC, a & (ONE - 1));
        Fixed(a_high * f + ((a_low * f + (1 << (FRAC - 1))) >> FRAC))
    }
    // As `mul_small`, with a_l f unsigned: below 2^14 2^18 = 2^32 for 0 <= f <= 2^18 raw (16).
    #[inline(always)]
    fn mul_nonnegative(self, factor: Self) -> Self {
        debug_assert!(
            (0..=16 << FRAC).contains(&factor.0),
            "mul_nonnegative factor {factor:?}"
        );
        let (a, f) = (self.0, factor.0);
        let (a_high, a_low) = (a >> FRAC, (a & (ONE - 1)) as u32);
        let low = (a_low * f as u32 + (1 << (FRAC - 1))) >> FRAC;
        Fixed(a_high * f + low as i32)
    }
    // The raw magnitude shifted by FRAC: 2^-14 of it, rounded down (a product rounds up at half
    // a unit, which at a magnitude below one time unit is more than 1e-4 of it).
    #[inline(always)]
    fn tie_band(self) -> Self {
        Fixed(self.0 >> FRAC)
    }
    // Inlined check, out-of-line root: where the caller has tested the value positive (Algorithm
    // 1's L^2 > 0), the check folds away.
    #[inline(always)]
    fn sqrt(self) -> Self {
        if self.0 > 0 {
            Fixed(sqrt_of_positive(self.0.unsigned_abs()))
        } else if self.is_invalid() {
            self
        } else {
            Fixed(0)
        }
    }
    fn sin_cos(self) -> (Self, Self) {
        if self.is_invalid() {
            return (self, self);
        }
        // The quarter turn and the position within it, from the binary angle; the cosine is
        // the sine of the rest of the quarter, 2^30 - 1 - position (the complement of its 30
        // bits; one unit short, 2^-30 of a quarter turn).
        let angle = binary_angle(self.0);
        let quarter = (1 << 30) - 1;
        let position = angle & quarter;
        let s = Fixed(quarter_sine(position));
        let c = Fixed(quarter_sine(position ^ quarter));
        match angle >> 30 {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        }
    }
    // Inlined into the bearing (35 fewer M0 instructions per evaluation for 152 B, measured
    // where the law's pair called it too; the pair reaches `angle_of` through
    // `tangent_heading`).
    #[inline(always)]
    fn atan2(y: Self, x: Self) -> Self {
        if y.is_invalid() || x.is_invalid() {
            return Fixed(INVALID);
        }
        Fixed(angle_of(y.0, x.0))
    }
    // The four scaled alike so that |d_x|, |d_y| <= 2^15 (`shift_below` of the one's-complement
    // magnitudes, below 2^22 in the envelope; the rounding may reach 2^15), each rounded: then
    // L, |k| <= |D| + 1 <= 2^15.5 + 1, and each product is one 32-bit product below 2^30.6,
    // halved before the sum. A scaled direction is within about 1.5 / |D| rad (|D| >= 2^14 once
    // scaled) of the exact one; unscaled (|D| below about 2 r_p), the operands are exact.
    #[inline(always)]
    fn tangent_heading(length: Self, k: Self, dx: Self, dy: Self) -> Self {
        let shift = shift_below(
            ones_complement_magnitude(dx.0) | ones_complement_magnitude(dy.0),
            15,
        );
        let half = (1 << shift) >> 1;
        let scaled = |v: Self| (v.0 + half) >> shift;
        let (l, k, dx, dy) = (scaled(length), scaled(k), scaled(dx), scaled(dy));
        let cos_psi = ((l * dx) >> 1) + ((k * dy) >> 1);
        let sin_psi = ((l * dy) >> 1) - ((k * dx) >> 1);
        // Products of 16-bit operands: never the invalid value, nothing to check.
        Fixed(angle_of(sin_psi, cos_psi))
    }
    // Both differences' signs in one test: self - low and high - self are both >= 0 exactly
    // when their OR is (two compares and their branches on a Cortex-M0; M0 1,935 -> 1,889 in
    // `cargo xtask profile`). Unchecked like `Sub`: the law's arcs and bounds are within 2 pi.
    #[inline(always)]
    fn between(self, low: Self, high: Self) -> bool {
        (self.0 - low.0) | (high.0 - self.0) >= 0
    }
    // Inlined: the law's headings arrive reduced ([`crate::Limits::states`]), and one comparison
    // in the caller is a tenth of a call.
    #[inline(always)]
    fn wrap_signed(self) -> Self {
        if self.0.unsigned_abs() <= PI_Q14 as u32 {
            return self;
        }
        self.wrap_signed_beyond_pi()
    }
    fn wrap_positive(self) -> Self {
        if self.is_invalid() {
            return self;
        }
        // The law's angles are differences of reduced headings, within a few turns: a few
        // subtractions instead of a division (a library call on a Cortex-M0).
        let mut v = self.0;
        if v.unsigned_abs() < 4 * TAU_Q14 as u32 {
            while v < 0 {
                v += TAU_Q14;
            }
            while v >= TAU_Q14 {
                v -= TAU_Q14;
            }
            return Fixed(v);
        }
        Fixed(self.0.rem_euclid(TAU_Q14))
    }
}

#[cfg(test)]
mod tests {
    use super::ratio_q15;

    /// The ratio behind `atan2` is within two units of the floor of low 2^15 / high: at low = high
    /// for every high below 2^17 (where the estimate is largest), on a stride of lows below, and on a
    /// stride of highs up to 2^32 (shifted down before the reciprocal).
    #[test]
    fn ratio_is_within_two_units_of_the_quotient() {
        let small = 1u32..1 << 17;
        let large = (1u32 << 17..u32::MAX).step_by(65_521);
        let mut worst = 0;
        for high in small.chain(large) {
            let lows = (0..high).step_by(((high / 61) as usize).max(1));
            for low in lows.chain([high]) {
                let exact = ((u64::from(low) << 15) / u64::from(high)) as u32;
                let got = ratio_q15(low, high);
                assert!(got.abs_diff(exact) <= 2, "{low} / {high}: {got} vs {exact}");
                worst = worst.max(got.abs_diff(exact));
            }
        }
        println!("ratio: at most {worst} units from the quotient");
    }
}
