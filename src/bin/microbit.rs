//! Firmware entry for the BBC micro:bit (nRF51822, Cortex-M0, no FPU), in QEMU's `microbit`
//! machine or on the board: TIMER0 and UART0, then the guidance loop with the fixed-point
//! (Q17.14) law; the wire's f32 values are converted with integers only. The exit code goes out
//! via semihosting under QEMU (0 after Shutdown, 1 on a failed start or a panic).
#![no_std]
#![no_main]

use cortex_m_semihosting::debug::{EXIT_FAILURE, EXIT_SUCCESS};
use twocars::board::exit_qemu as halt;
use twocars::board::microbit::{take_uart, Microbit};
use twocars::num::fixed::Fixed;
use twocars::protocol::endpoint::Endpoint;
use twocars::serial::serve_to_shutdown;

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(peripherals) = nrf51_pac::Peripherals::take() else {
        halt(EXIT_FAILURE)
    };
    let board = Microbit::start(peripherals.TIMER0);
    let Some(mut line) = take_uart() else {
        halt(EXIT_FAILURE)
    };
    let mut unit = Endpoint::<Fixed>::new();
    serve_to_shutdown(&mut line, &board, &mut unit);
    halt(EXIT_SUCCESS)
}

// The flight build (`panic-never`) takes the board module's link-time check instead.
#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    halt(EXIT_FAILURE)
}
