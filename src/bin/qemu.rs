//! Firmware entry for QEMU `mps2-an386`: board init, then the guidance loop. Logs go out as
//! defmt over semihosting with the `qemu-log` feature; the exit code via semihosting (0 after
//! Shutdown, 1 on a failed start or a panic).
#![no_std]
#![no_main]

use cortex_m_semihosting::debug::{EXIT_FAILURE, EXIT_SUCCESS};
#[cfg(feature = "qemu-log")]
use defmt_semihosting as _;
use twocars::board::exit_qemu as halt;
use twocars::board::qemu_mps2::{take_uart, Mps2};
use twocars::protocol::endpoint::Endpoint;
use twocars::serial::serve_to_shutdown;

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        halt(EXIT_FAILURE)
    };
    let board = Mps2::start(peripherals.SYST);
    let Some(mut line) = take_uart() else {
        halt(EXIT_FAILURE)
    };
    let mut unit = Endpoint::<f32>::new();
    #[cfg(feature = "tables-in-flash")]
    if let Some(tables) = twocars::board::tables::take_value_tables() {
        unit.set_tables(tables);
    }
    #[cfg(feature = "defmt")]
    defmt::info!("twocars guidance unit up (mps2-an386, UART0, interrupt-driven)");
    serve_to_shutdown(&mut line, &board, &mut unit);
    let _c = unit.counters();
    let _f = line.faults();
    #[cfg(feature = "defmt")]
    defmt::info!(
        "shutdown: {=u32} messages accepted, {=u32} refused, {=u32} watchdog expiries, {=u32} overruns, {=u32} replies dropped",
        _c.accepted,
        _c.errors.iter().sum::<u32>(),
        _c.stale,
        _f.overrun,
        _f.tx_full
    );
    halt(EXIT_SUCCESS)
}

// The flight build (`panic-never`) takes the board module's link-time check instead.
#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    halt(EXIT_FAILURE)
}
