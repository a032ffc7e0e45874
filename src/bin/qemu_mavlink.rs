//! Firmware entry for QEMU `mps2-an386` speaking MAVLink 2 (docs/mavlink.md): board init, then
//! the endpoint on UART0 for good. Exit code 1 over semihosting on a failed start or a panic.
#![no_std]
#![no_main]

use cortex_m_semihosting::debug::EXIT_FAILURE;
use twocars::board::exit_qemu as halt;
use twocars::board::qemu_mps2::{take_uart, Mps2};
use twocars::mavlink::service::serve_mavlink;
use twocars::mavlink::Endpoint;

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        halt(EXIT_FAILURE)
    };
    let board = Mps2::start(peripherals.SYST);
    let Some(mut line) = take_uart() else {
        halt(EXIT_FAILURE)
    };
    let mut endpoint = Endpoint::provisioned();
    serve_mavlink(&mut line, &board, &mut endpoint)
}

// The flight build (`panic-never`) takes the board module's link-time check instead.
#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    halt(EXIT_FAILURE)
}
