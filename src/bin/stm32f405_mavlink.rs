//! Firmware entry for STM32F405 flight controllers speaking MAVLink 2 to the autopilot
//! (docs/mavlink.md): clocks, USART1 at 115200 baud, then the endpoint for good. A flight
//! build: no log transport; only a failed start or a panic resets the MCU.
#![no_std]
#![no_main]

use twocars::board::stm32f405::bring_up;
use twocars::mavlink::service::serve_mavlink;
use twocars::mavlink::Endpoint;

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some((board, _serial, mut line)) = bring_up() else {
        cortex_m::peripheral::SCB::sys_reset()
    };
    let mut endpoint = Endpoint::provisioned();
    serve_mavlink(&mut line, &board, &mut endpoint)
}

// The flight build (`panic-never`) takes the board module's link-time check instead.
#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
}
