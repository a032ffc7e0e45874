//! Firmware entry for STM32F405 flight controllers speaking MAVLink 2 to the autopilot
//! (docs/mavlink.md): clocks, USART1 at 115200 baud, then the endpoint for good. A flight
//! build: no log transport; only a failed start or a panic resets the MCU.
#![no_std]
#![no_main]

use stm32f4xx_hal::pac;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::Config;
use stm32f4xx_hal::serial::Serial;
use twocars::board::stm32f405::{take_uart, Stm32f405};
use twocars::mavlink::service::serve_mavlink;
use twocars::mavlink::Endpoint;

/// Core clock, Hz.
const SYSCLK_HZ: u32 = 168_000_000;

#[cortex_m_rt::entry]
fn main() -> ! {
    let (Some(dp), Some(cp)) = (pac::Peripherals::take(), cortex_m::Peripherals::take()) else {
        cortex_m::peripheral::SCB::sys_reset()
    };
    let mut rcc = dp.RCC.freeze(Config::hse(8.MHz()).sysclk(SYSCLK_HZ.Hz()));
    let gpioa = dp.GPIOA.split(&mut rcc);
    let Ok(serial) = Serial::new(dp.USART1, (gpioa.pa9, gpioa.pa10), 115_200.bps(), &mut rcc)
    else {
        cortex_m::peripheral::SCB::sys_reset()
    };
    let board = Stm32f405::start(cp.SYST, SYSCLK_HZ);
    let Some((_serial, mut line)) = take_uart(serial) else {
        cortex_m::peripheral::SCB::sys_reset()
    };
    let mut endpoint = Endpoint::new();
    serve_mavlink(&mut line, &board, &mut endpoint)
}

// The flight build (`panic-never`) takes the board module's link-time check instead.
#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
}
