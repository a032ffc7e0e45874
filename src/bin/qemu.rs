//! Firmware entry for QEMU `mps2-an386`: board init, then the guidance loop. Logs go out as
//! defmt over semihosting with the `qemu-log` feature; the exit code via semihosting (0 after
//! Shutdown, 1 on a failed start or a panic).
#![no_std]
#![no_main]

use cortex_m_semihosting::debug::{exit, EXIT_FAILURE, EXIT_SUCCESS};
#[cfg(feature = "qemu-log")]
use defmt_semihosting as _;
use twocars::board::qemu_mps2::{take_uart, Mps2};
use twocars::serial::{serve, Board};
use twocars::unit::Unit;

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        halt(EXIT_FAILURE)
    };
    let board = Mps2::start(peripherals.SYST);
    let Some(mut line) = take_uart() else {
        halt(EXIT_FAILURE)
    };
    let mut unit = Unit::<f32>::new();
    twocars::log_info!("twocars guidance unit up (mps2-an386, UART0, interrupt-driven)");
    serve(&mut line, &board, &mut unit);
    // The ShutdownAck is queued: let the transmit interrupt send it before QEMU exits.
    while !line.all_sent() {
        board.sleep_while(&mut || !line.all_sent());
    }
    let _c = unit.counters();
    let _f = line.faults();
    twocars::log_info!(
        "shutdown: {=u32} messages accepted, {=u32} refused, {=u32} watchdog expiries, {=u32} overruns, {=u32} replies dropped",
        _c.accepted,
        _c.errors.iter().sum::<u32>(),
        _c.stale,
        _f.overrun,
        _f.tx_full
    );
    halt(EXIT_SUCCESS)
}

/// Ends the QEMU session with `code`; sleeps if semihosting exit returns (not under QEMU).
fn halt(code: cortex_m_semihosting::debug::ExitStatus) -> ! {
    exit(code);
    loop {
        cortex_m::asm::wfi();
    }
}

#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    halt(EXIT_FAILURE)
}

#[cfg(feature = "panic-never")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    unsafe extern "C" {
        /// Defined nowhere: linking fails if any panic path survives optimisation.
        fn twocars_panic_path_is_reachable() -> !;
    }
    // SAFETY: never called in an image that links.
    unsafe { twocars_panic_path_is_reachable() }
}
