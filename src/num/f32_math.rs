//! The f32 backend's own transcendental functions: short polynomials after a cheap range
//! reduction, and the FPU's square root where there is one. `libm`'s `sinf`/`cosf` work in f64
//! internally and `sqrtf` never uses VSQRT: on a Cortex-M4F they cost thousands of soft-float
//! instructions per law evaluation (see `docs/bench.md`).
//!
//! Error bounds, checked against f64 by `cargo test -p host-tests --test f32_math` over the whole
//! envelope (|x| <= 1e4 rad for sine and cosine):
//! - [`sin_cos`]: absolute error <= 1e-7 for |x| <= 1e4 (measured 7.7e-8);
//! - [`atan2`]: absolute error <= 3e-7 rad (measured 2.65e-7, in the octants beside +-pi, where
//!   pi itself rounds);
//! - [`sqrt`]: correctly rounded with VSQRT; <= 1 ulp in the software fallback;
//! - [`wrap_signed`]: absolute error <= 3e-7 rad for |x| <= 1e4 (measured 1.2e-7).
//!
//! The sine and cosine coefficients are the single-precision minimax fits of the Cephes library
//! (S. L. Moshier), used within the same reduced range; the arctangent's are fitted here
//! (`atan_unit`).

use core::f32::consts::{FRAC_PI_2, PI};

/// pi/2 split in three parts for Cody-Waite reduction: `k * PIO2_HI` and `k * PIO2_MID` are
/// exact for |k| < 2^16 (|x| < 1e5).
const PIO2_HI: f32 = 1.570_312_5;
const PIO2_MID: f32 = 4.837_513e-4;
const PIO2_LO: f32 = 7.549_79e-8;
const TWO_OVER_PI: f32 = core::f32::consts::FRAC_2_PI;

/// Rounds to the nearest integer (ties away from zero) for |x| < 2^31; the saturating cast never
/// panics.
fn round_to_i32(x: f32) -> i32 {
    let half = if x < 0.0 { -0.5 } else { 0.5 };
    (x + half) as i32
}

/// The angle x (radians, |x| <= 1e5) reduced to [-pi, pi]: x - 2 pi round(x / 2 pi) with 2 pi in
/// the three parts of the sine's reduction, so a heading of 1e4 rad loses no more than one of
/// pi/4 (a single f32 2 pi would be 3e-4 rad off there).
pub fn wrap_signed(x: f32) -> f32 {
    // Most headings arrive reduced already: one compare inline, the reduction out of line.
    if x.abs() <= PI {
        return x;
    }
    wrap_signed_beyond_pi(x)
}

/// [`wrap_signed`] of an angle beyond [-pi, pi].
#[inline(never)]
fn wrap_signed_beyond_pi(x: f32) -> f32 {
    let k = round_to_i32(x * (0.25 * TWO_OVER_PI)) as f32;
    ((x - k * (4.0 * PIO2_HI)) - k * (4.0 * PIO2_MID)) - k * (4.0 * PIO2_LO)
}

/// sin and cos of r in [-pi/4, pi/4].
fn sin_cos_reduced(r: f32) -> (f32, f32) {
    let z = r * r;
    let sin = ((-1.951_529_6e-4 * z + 8.332_161e-3) * z - 1.666_665_5e-1) * z * r + r;
    let cos = ((2.443_315_7e-5 * z - 1.388_731_6e-3) * z + 4.166_664_6e-2) * z * z - 0.5 * z + 1.0;
    (sin, cos)
}

/// `(sin x, cos x)` for |x| <= 1e5 radians (beyond, the reduction loses accuracy; the law's
/// envelope is |theta| <= 1e4).
pub fn sin_cos(x: f32) -> (f32, f32) {
    let k = round_to_i32(x * TWO_OVER_PI);
    let kf = k as f32;
    let r = ((x - kf * PIO2_HI) - kf * PIO2_MID) - kf * PIO2_LO;
    let (s, c) = sin_cos_reduced(r);
    match k & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// atan(t) for t in [0, 1]: t + t^3 P(t^2), P of degree 7 fitted here to the least largest
/// error on [0, 1] (7.6e-8 rad evaluated in f32), so that an octant needs one division and no
/// further reduction.
fn atan_unit(t: f32) -> f32 {
    let z = t * t;
    let p = ((((((2.622_241_9e-3 * z - 1.513_252_6e-2) * z + 4.112_184_4e-2) * z - 7.366_705e-2)
        * z
        + 1.057_393_2e-1)
        * z
        - 1.418_597_5e-1)
        * z
        + 1.999_039_7e-1)
        * z
        - 3.333_298_6e-1;
    p * z * t + t
}

/// The angle of (x, y) in (-pi, pi] radians; 0 for the zero vector. Inlined into its callers (the
/// law's pair and the fallback's bearing): on a Cortex-M4F a call costs 17 instructions a
/// tangent, 69 an evaluation, against 248 B of law flash for the two copies
/// (`docs/optimisation.md`).
#[inline(always)]
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    if ax == 0.0 && ay == 0.0 {
        return 0.0;
    }
    // The octant's angle from the ratio of the smaller to the larger component.
    let steep = ay > ax;
    let (smaller, larger) = if steep { (ax, ay) } else { (ay, ax) };
    let a = atan_unit(smaller / larger);
    let a = if steep { FRAC_PI_2 - a } else { a };
    let a = if x < 0.0 { PI - a } else { a };
    if y < 0.0 {
        -a
    } else {
        a
    }
}

/// Square root of a non-negative value (0 for negative input): VSQRT on a Cortex-M with a
/// single-precision FPU. (Rust's `sreg` operands need the double-precision `vfp2` feature, which
/// these FPUs lack, so the value passes through a core register and s0 is declared clobbered.)
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
pub fn sqrt(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    let bits: u32;
    // SAFETY: writes only s0, declared clobbered, and the two operand registers; VSQRT.F32
    // exists on every eabihf Cortex-M FPU.
    unsafe {
        core::arch::asm!(
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {r}, s0",
            x = in(reg) x.to_bits(),
            r = lateout(reg) bits,
            out("s0") _,
            options(pure, nomem, nostack, preserves_flags),
        );
    }
    f32::from_bits(bits)
}

/// Square root of a non-negative value (0 for negative input); `libm` where there is no FPU.
#[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
pub fn sqrt(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    libm::sqrtf(x)
}
