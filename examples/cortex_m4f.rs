//! A firmware's control loop on a Cortex-M4F with the f32 law, run in QEMU (mps2-an386) over
//! semihosting: the loop of `chase/mod.rs` on `f32`.
//!
//! ```sh
//! cargo run --release --example cortex_m4f --target thumbv7em-none-eabihf --features board-qemu
//! ```
#![no_std]
#![no_main]

mod chase;

#[cortex_m_rt::entry]
fn main() -> ! {
    chase::run::<f32>()
}
