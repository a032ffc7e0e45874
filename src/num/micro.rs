//! The `micromath` backend: f32 arithmetic with micromath's fast approximations of square root,
//! sine, cosine and arctangent. No error bound is promised (micromath quotes ~1e-3 for sin/cos,
//! ~3e-3 for atan2 and up to several percent for sqrt); the measured error of the whole law is
//! reported by `cargo test -p host-tests --test backends -- --nocapture`.

use core::ops::{Add, Div, Mul, Neg, Sub};

use micromath::F32Ext;

use super::Scalar;

/// An f32 whose transcendental functions come from `micromath`.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd, Default)]
pub struct Micro(pub f32);

macro_rules! binary {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Micro {
            type Output = Micro;
            fn $method(self, rhs: Micro) -> Micro {
                Micro(self.0 $op rhs.0)
            }
        }
    };
}

binary!(Add, add, +);
binary!(Sub, sub, -);
binary!(Mul, mul, *);
binary!(Div, div, /);

impl Neg for Micro {
    type Output = Micro;
    fn neg(self) -> Micro {
        Micro(-self.0)
    }
}

impl super::sealed::Sealed for Micro {}

impl Scalar for Micro {
    const MAX_COORDINATE: f32 = 1.0e6;
    const MAX_HEADING: f32 = 1.0e4;
    const TIE_BAND: f32 = 1.0e-4;
    // micromath's atan2 is off by up to ~3e-3 rad: an arc within that of 0 or 2 pi is the tangent.
    const ARC_RESOLUTION: f32 = 5.0e-3;

    fn from_f32(value: f32) -> Self {
        Micro(value)
    }
    fn to_f32(self) -> f32 {
        self.0
    }
    fn to_f64(self) -> f64 {
        f64::from(self.0)
    }
    fn pi() -> Self {
        Micro(core::f32::consts::PI)
    }
    fn never() -> Self {
        Micro(f32::MAX)
    }
    fn tau() -> Self {
        Micro(core::f32::consts::TAU)
    }
    fn sqrt(self) -> Self {
        if self.0 > 0.0 {
            Micro(F32Ext::sqrt(self.0))
        } else {
            Micro(0.0)
        }
    }
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = F32Ext::sin_cos(self.0);
        (Micro(s), Micro(c))
    }
    fn atan2(y: Self, x: Self) -> Self {
        if y.0 == 0.0 && x.0 == 0.0 {
            return Micro(0.0);
        }
        Micro(F32Ext::atan2(y.0, x.0))
    }
    fn wrap_positive(self) -> Self {
        // Plain f32 arithmetic: the f32 backend's reduction.
        Micro(self.0.wrap_positive())
    }
    fn wrap_signed(self) -> Self {
        Micro(self.0.wrap_signed())
    }
    fn abs(self) -> Self {
        Micro(f32::abs(self.0))
    }
}
