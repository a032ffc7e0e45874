//! The guidance unit on a HAL's UART: stm32f4xx-hal's `Serial` on USART1 (PA9 TX, PA10 RX,
//! 115200 8N1), polled through embedded-hal-nb's serial traits by `twocars::polled::serve`, the
//! clock the board's 1 kHz SysTick. Our frames in, Commands out, as the interrupt-driven
//! `twocars-stm32f405` image answers them; that image stays the flight path (a polled loop that
//! is busy with the law for a period can lose bytes the UART's one-byte buffer cannot hold).
//!
//! ```sh
//! cargo build --release --example stm32f4_hal --target thumbv7em-none-eabihf --features board-stm32f405,polled
//! ```
#![no_std]
#![no_main]

use cortex_m::peripheral::SCB;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::Config;
use stm32f4xx_hal::{pac, serial::Serial};
use twocars::board::stm32f405::{Stm32f405, SYSCLK_HZ};
use twocars::protocol::endpoint::Endpoint;
use twocars::serial::Board;

#[cortex_m_rt::entry]
fn main() -> ! {
    let (Some(dp), Some(cp)) = (pac::Peripherals::take(), cortex_m::Peripherals::take()) else {
        SCB::sys_reset()
    };
    // Clocks from the 8 MHz crystal, USART1 on its pins: the HAL's work.
    let mut rcc = dp.RCC.freeze(Config::hse(8.MHz()).sysclk(SYSCLK_HZ.Hz()));
    let gpioa = dp.GPIOA.split(&mut rcc);
    let baud = 115_200.bps();
    let Ok(mut serial) = Serial::new(dp.USART1, (gpioa.pa9, gpioa.pa10), baud, &mut rcc) else {
        SCB::sys_reset()
    };
    let board = Stm32f405::start(cp.SYST, SYSCLK_HZ);
    // The guidance unit: configured by the first Configure frame, as over any link.
    let mut unit = Endpoint::<f32>::new();
    loop {
        // A port fault (overrun, framing) loses a byte; the frame's CRC refuses what it broke,
        // so serving goes on. After a Shutdown a flight unit keeps serving too.
        let _ = twocars::polled::serve(&mut serial, &mut unit, || board.now_ms());
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    SCB::sys_reset()
}
