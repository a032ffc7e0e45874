//! Board shells: registers and clocks only; the loop is [`crate::firmware::serve`].
#![allow(unsafe_code)]

#[cfg(feature = "board-qemu")]
pub mod qemu_mps2;

#[cfg(feature = "board-stm32f405")]
pub mod stm32f405;
