//! Firmware entry for STM32F405 flight controllers: clocks, USART1, then the guidance loop.
//! A flight build: no log transport. Line faults are counted, not fatal; only a failed start or
//! a panic resets the MCU.
#![no_std]
#![no_main]

use twocars::board::stm32f405::bring_up;
use twocars::protocol::endpoint::Endpoint;
use twocars::serial::serve;

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some((board, _serial, mut line)) = bring_up() else {
        cortex_m::peripheral::SCB::sys_reset()
    };
    let mut unit = Endpoint::<f32>::new();
    #[cfg(feature = "tables-in-flash")]
    if let Some(tables) = twocars::board::tables::take_value_tables() {
        unit.set_tables(tables);
    }
    loop {
        // A flight unit has no session to end: after a Shutdown it keeps serving.
        serve(&mut line, &board, &mut unit);
    }
}

// The flight build (`panic-never`) takes the board module's link-time check instead.
#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
}
