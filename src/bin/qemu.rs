//! Firmware entry for QEMU `mps2-an386`: board init, then the guidance loop. Logs go out as
//! defmt over semihosting; the exit code too (0 after Shutdown, 1 on a port error or panic).
#![no_std]
#![no_main]

use cortex_m_semihosting::debug::{exit, EXIT_FAILURE, EXIT_SUCCESS};
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
    defmt::info!("twocars guidance unit up (mps2-an386, UART0)");
    let code = match serve(&mut uart, &clock, &mut unit) {
        Stop::Shutdown => EXIT_SUCCESS,
        Stop::Serial(e) => match e {},
    };
    let c = unit.counters();
    defmt::info!(
        "shutdown: {=u32} messages accepted, {=u32} refused, {=u32} watchdog expiries",
        c.accepted,
        c.errors.iter().sum::<u32>(),
        c.stale
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

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    halt(EXIT_FAILURE)
}
