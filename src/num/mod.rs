//! The number types the law is written over.
//!
//! The law in [`crate::law::geometry`], [`crate::law::capture`], [`crate::law::game`] and [`crate::law`] is written
//! once, over [`Scalar`]. A backend supplies arithmetic, the few transcendental functions the law
//! needs (square root, sine and cosine, two-argument arctangent) and its envelope: the inputs it
//! represents faithfully. Implemented here: `f32` (the accurate default: our own polynomials and
//! the FPU's square root, [`f32_math`]), `f64` (the reference-grade path, via `libm`, that the
//! host tests compare against), [`fixed::Fixed`] (Q17.14 for cores without an FPU, normalised)
//! and, with the `micromath` feature, `micro::Micro` (micromath's approximations).

pub mod convert;
pub mod f32_math;
pub mod fixed;
pub mod ieee;
#[cfg(feature = "micromath")]
pub mod micro;

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::error::Error;
use convert::Reciprocal;

/// The backends this crate implements; [`Scalar`] is sealed: its conversions rest on the
/// crate's integer conversions ([`convert`]), so the backends are the crate's own.
mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A real number as one numeric backend represents it: `f32`, `f64`, [`fixed::Fixed`] and,
/// with the `micromath` feature, `micro::Micro` (sealed: no other type implements it).
///
/// Angles are in radians, anticlockwise from +x.
pub trait Scalar:
    sealed::Sealed
    + Copy
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Largest |x|, |y| this backend accepts in the law's frame (metres; pursuer radii from the
    /// pursuer if [`Scalar::NORMALISED`]); beyond it the law reports `out_of_range`.
    const MAX_COORDINATE: f32;
    /// Largest |theta| (radians) this backend accepts; beyond it the law reports `out_of_range`.
    const MAX_HEADING: f32;
    /// Relative tie band of the matrix game: values within `TIE_BAND * max(|a|, |b|)` count as equal.
    /// At most 1e-4 by contract.
    const TIE_BAND: f32;
    /// Smallest arc (radians) this backend resolves: an arc within it of 2 pi counts as 0, so a
    /// vehicle on its tangent is not sent round a full circle by rounding.
    const ARC_RESOLUTION: f32;
    /// Whether the law runs normalised on this backend: lengths in units of the pursuer's turning
    /// radius, times in units of r_p / v_pm, positions relative to the pursuer
    /// ([`crate::Limits::states`]), so that a narrow number range covers every vehicle scale.
    const NORMALISED: bool = false;
    /// Largest r_e / r_p (= w_pm / w_em) this backend accepts; beyond it `out_of_range`.
    const MAX_RADIUS_RATIO: f32 = f32::INFINITY;
    /// Smallest v_em / v_pm this backend accepts; below it `out_of_range`.
    const MIN_SPEED_RATIO: f32 = 0.0;
    /// Largest v_em / v_pm this backend accepts (the closing speed's floor); above it
    /// `out_of_range`.
    const MAX_SPEED_RATIO: f32 = 1.0;
    /// Largest magnitude, in the law's units, of a control period's terms on this backend: the
    /// period dt plus the tie floor, and a full turn's curvature 2 pi / (v_max dt) of each vehicle.
    /// [`crate::Guidance::new`] refuses a period beyond it, so that a sampled caller's products
    /// stay in the backend's range (fixed point's arithmetic is not checked at run time).
    const MAX_PERIOD_TERM: f32 = f32::INFINITY;

    /// Converts from `f32`; the caller has checked the value is finite and inside the envelope.
    fn from_f32(value: f32) -> Self;
    /// Converts from `f32`, rounding toward zero where the backend rounds at all: a limit never
    /// grows in conversion (a commanded curvature stays within the true w_max).
    fn from_f32_toward_zero(value: f32) -> Self {
        Self::from_f32(value)
    }
    /// Converts to `f32` (for reports and the wire).
    fn to_f32(self) -> f32;
    /// A law value in the wire's units, `self * scale` as an `f32`, `scale` being the wire units
    /// per law unit: 1 on an SI backend, whose value is taken as it is. Fixed point forms the
    /// exact product with integers and rounds it once (no soft-float call).
    #[inline(always)]
    fn to_f32_scaled(self, scale: f32) -> f32 {
        if Self::NORMALISED {
            self.to_f32() * scale
        } else {
            self.to_f32()
        }
    }
    /// On a normalised backend: the evader's offset from the pursuer, `(x, y)` each as
    /// (pursuer, evader) in metres (finite, within the f32 envelope), in units of `metres`
    /// (`per_metre` its reciprocal); `OutOfRange` where the players are apart by more than
    /// `radius` units yet both offsets round to zero (the backend would read one point).
    /// Fixed point converts with integers only ([`convert`]), `per_metre` its reciprocal of
    /// the unit.
    fn relative_position(
        x: (f32, f32),
        y: (f32, f32),
        metres: f32,
        per_metre: &Reciprocal,
        radius: f32,
    ) -> Result<(Self, Self), Error> {
        let _ = per_metre;
        let (dx, dy) = ((x.1 - x.0) / metres, (y.1 - y.0) / metres);
        let (sx, sy) = (Self::from_f32(dx), Self::from_f32(dy));
        if sx == Self::zero() && sy == Self::zero() && dx * dx + dy * dy > radius * radius {
            return Err(Error::OutOfRange);
        }
        Ok((sx, sy))
    }
    /// On a normalised backend: a finite heading (radians) reduced to [-pi, pi].
    fn reduced_heading(theta: f32) -> Self {
        Self::from_f32(f32_math::wrap_signed(theta))
    }
    /// Converts to `f64` (for reports on the host).
    fn to_f64(self) -> f64;
    /// Whether the value is a number: false only where a backend's arithmetic left its range
    /// (fixed point's invalid value), which the law reports as `out_of_range`.
    fn is_valid(self) -> bool {
        true
    }
    /// Whether the value is a number: valid, and not a NaN.
    fn is_number(self) -> bool {
        self.is_valid() && self.partial_cmp(&self).is_some()
    }
    /// Square root of a non-negative value; 0 for negative input.
    fn sqrt(self) -> Self;
    /// `(sin(angle), cos(angle))` of an angle in radians.
    fn sin_cos(self) -> (Self, Self);
    /// Angle of the vector `(x, y)` in radians, in (-pi, pi]; 0 for the zero vector.
    fn atan2(y: Self, x: Self) -> Self;
    /// Angle (radians, in (-pi, pi]) of Algorithm 1's tangent direction L D + k D_perp =
    /// (L d_x + k d_y, L d_y - k d_x), for L, |k| <= |D| (a valid tangent). Only the direction
    /// counts, so a backend may scale the four alike before its products.
    #[inline(always)]
    fn tangent_heading(length: Self, k: Self, dx: Self, dy: Self) -> Self {
        Self::atan2(length * dy - k * dx, length * dx + k * dy)
    }
    /// The angle reduced to [0, 2 pi).
    fn wrap_positive(self) -> Self;
    /// The angle reduced to [-pi, pi] (the law's headings: one reduction per heading, so that a
    /// difference of two reduced angles wraps with one addition).
    fn wrap_signed(self) -> Self {
        let positive = self.wrap_positive();
        if positive > Self::pi() {
            positive - Self::tau()
        } else {
            positive
        }
    }

    /// A time (seconds) beyond every capture time the law computes inside this backend's
    /// envelope, with room to subtract any of them: the matrix game's infinity, the entry of a
    /// pair without a valid tangent.
    fn never() -> Self;

    /// `self * factor` for a `factor` below 8 in magnitude in the law's units on a normalised
    /// backend: a sine or cosine (or one times r_p = 1), an angle of at most 2 pi (an arc, a
    /// bearing's magnitude), a difference of unit normals or its square (at most 4), a speed
    /// ratio (the evader's speed, below v_pm = 1). On fixed point two integer
    /// multiplications where a product of any two values takes four; `*` elsewhere.
    #[inline(always)]
    fn mul_small(self, factor: Self) -> Self {
        self * factor
    }

    /// The tie band around a magnitude `self` >= 0 (seconds): `self * TIE_BAND`, never more than
    /// that on fixed point (the game's ties, [`crate::law::game::ties_within`]). On fixed point a
    /// shift; a product elsewhere.
    #[inline(always)]
    fn tie_band(self) -> Self {
        self.mul_small(Self::from_f32(Self::TIE_BAND))
    }

    /// `self * factor` for a `factor` in [0, 16] in the law's units on a normalised backend: the
    /// closing time per metre 1 / (v_pm - v_em) (at most 16 where v_em <= 15/16 v_pm). On fixed
    /// point two integer multiplications, as [`Scalar::mul_small`], the one of the low bits
    /// unsigned; `*` elsewhere.
    #[inline(always)]
    fn mul_nonnegative(self, factor: Self) -> Self {
        self * factor
    }

    /// Zero.
    fn zero() -> Self {
        Self::from_f32(0.0)
    }
    /// One.
    fn one() -> Self {
        Self::from_f32(1.0)
    }
    /// pi, to this backend's precision.
    fn pi() -> Self;
    /// 2 pi, to this backend's precision.
    fn tau() -> Self;
    /// Absolute value.
    fn abs(self) -> Self {
        if self < Self::zero() {
            -self
        } else {
            self
        }
    }
    /// The larger of two values.
    fn max(self, other: Self) -> Self {
        if other > self {
            other
        } else {
            self
        }
    }
    /// The smaller of two values.
    fn min(self, other: Self) -> Self {
        if other < self {
            other
        } else {
            self
        }
    }
    /// Whether `low <= self <= high` (false for a NaN): the arc test of
    /// [`crate::Direction::arc_to`].
    #[inline(always)]
    fn between(self, low: Self, high: Self) -> bool {
        low <= self && self <= high
    }
}

impl Scalar for f32 {
    const MAX_COORDINATE: f32 = 1.0e6;
    const MAX_HEADING: f32 = 1.0e4;
    const TIE_BAND: f32 = 1.0e-4;
    const ARC_RESOLUTION: f32 = 1.0e-5;

    fn from_f32(value: f32) -> Self {
        value
    }
    fn to_f32(self) -> f32 {
        self
    }
    fn pi() -> Self {
        core::f32::consts::PI
    }
    fn never() -> Self {
        f32::MAX
    }
    fn tau() -> Self {
        core::f32::consts::TAU
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn sqrt(self) -> Self {
        f32_math::sqrt(self)
    }
    fn sin_cos(self) -> (Self, Self) {
        f32_math::sin_cos(self)
    }
    #[inline(always)]
    fn atan2(y: Self, x: Self) -> Self {
        f32_math::atan2(y, x)
    }
    fn wrap_signed(self) -> Self {
        f32_math::wrap_signed(self)
    }

    fn abs(self) -> Self {
        // VABS: one instruction where the default's compare and select are four.
        f32::abs(self)
    }
    fn wrap_positive(self) -> Self {
        // The signed reduction (2 pi in three parts) and a turn added below zero: one f32 2 pi
        // times the turns puts fixed point's headings 7.5e-4 rad off at 1e4 rad.
        let tau = core::f32::consts::TAU;
        let signed = f32_math::wrap_signed(self);
        let wrapped = if signed < 0.0 { signed + tau } else { signed };
        // A hair below zero plus 2 pi rounds to 2 pi: fold it back into [0, 2 pi).
        if wrapped >= tau {
            0.0
        } else {
            wrapped
        }
    }
}

impl Scalar for f64 {
    const MAX_COORDINATE: f32 = 1.0e6;
    const MAX_HEADING: f32 = 1.0e4;
    const TIE_BAND: f32 = 1.0e-9;
    const ARC_RESOLUTION: f32 = 1.0e-9;

    fn from_f32(value: f32) -> Self {
        f64::from(value)
    }
    fn to_f32(self) -> f32 {
        // Reports only: the law itself never narrows.
        self as f32
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn pi() -> Self {
        core::f64::consts::PI
    }
    fn never() -> Self {
        f64::MAX
    }
    fn tau() -> Self {
        core::f64::consts::TAU
    }
    fn sqrt(self) -> Self {
        if self > 0.0 {
            libm::sqrt(self)
        } else {
            0.0
        }
    }
    fn sin_cos(self) -> (Self, Self) {
        libm::sincos(self)
    }
    fn atan2(y: Self, x: Self) -> Self {
        libm::atan2(y, x)
    }
    fn wrap_positive(self) -> Self {
        let tau = core::f64::consts::TAU;
        let wrapped = self - tau * libm::floor(self / tau);
        if wrapped >= tau || wrapped < 0.0 {
            0.0
        } else {
            wrapped
        }
    }
}
