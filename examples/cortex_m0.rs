//! A firmware's control loop on a Cortex-M0 with the Q17.14 fixed-point law (no FPU), run in
//! QEMU (micro:bit) over semihosting: the loop of `chase/mod.rs` on `twocars::Fixed` (the plant
//! simulation stays in soft-float f32, as sensors would be outside the law).
//!
//! ```sh
//! cargo run --release --example cortex_m0 --target thumbv6m-none-eabi --features board-microbit
//! ```
#![no_std]
#![no_main]

mod chase;

#[cortex_m_rt::entry]
fn main() -> ! {
    chase::run::<twocars::Fixed>()
}
