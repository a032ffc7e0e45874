//! Firmware entry for QEMU `mps2-an386`: board init, then the guidance loop. Logs go out as
//! defmt over semihosting with the `qemu-log` feature; the exit code via semihosting (0 after
//! Shutdown, 1 on a port error or panic).
#![no_std]
#![no_main]

use cortex_m_semihosting::debug::{exit, EXIT_FAILURE, EXIT_SUCCESS};
#[cfg(feature = "qemu-log")]
use defmt_semihosting as _;
use twocars::board::qemu_mps2::{SysTickClock, Uart};
use twocars::firmware::{serve, Stop};
use twocars::unit::Unit;

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        halt(EXIT_FAILURE)
    };
    let clock = SysTickClock::start(peripherals.SYST);
    // SAFETY: the only owner of UART0.
    let mut uart = unsafe { Uart::take() };
    let mut unit = Unit::new();
    twocars::log_info!("twocars guidance unit up (mps2-an386, UART0)");
    let code = match serve(&mut uart, &clock, &mut unit) {
        Stop::Shutdown => EXIT_SUCCESS,
        Stop::Serial(e) => match e {},
    };
    let _c = unit.counters();
    twocars::log_info!(
        "shutdown: {=u32} messages accepted, {=u32} refused, {=u32} watchdog expiries",
        _c.accepted,
        _c.errors.iter().sum::<u32>(),
        _c.stale
    );
    halt(code)
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
