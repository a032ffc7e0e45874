//! What every bench image measures with: SysTick on the processor clock (under QEMU's `-icount`
//! its ticks count instructions), a painted stack for the high-water mark, and semihosting to
//! print and to exit. A panic exits with failure, so the host never reads a half-run as figures.

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_semihosting::debug::{exit, EXIT_FAILURE, EXIT_SUCCESS};

const PAINT: u32 = 0xA5A5_5A5A;
/// Bytes of stack painted below the caller's frame: 16 KiB on the M4F's board (mps2-an386,
/// 4 MB of RAM), where the MAVLink path's replay goes past 4 KiB; 4 KiB on the M0's.
#[cfg(target_abi = "eabihf")]
const PAINT_BYTES: usize = 16 * 1024;
#[cfg(not(target_abi = "eabihf"))]
const PAINT_BYTES: usize = 4096;

/// Starts SysTick on the processor clock, counting down from its 24-bit maximum; exits with
/// failure if the core peripherals were taken already.
pub fn start() {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        fail();
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00FF_FFFF);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();
}

/// The SysTick counter now (it counts down).
pub fn now() -> u32 {
    cortex_m::peripheral::SYST::get_current()
}

/// SysTick ticks from `start` to now (the counter counts down, 24 bits).
pub fn ticks_since(start: u32) -> u32 {
    start.wrapping_sub(now()) & 0x00FF_FFFF
}

/// Paints the stack below the caller's frame; the bottom of the painted region, for [`used`].
pub fn paint() -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let bottom = sp - PAINT_BYTES;
    let mut a = bottom;
    while a < sp - 64 {
        // SAFETY: below the live stack pointer, inside RAM: unused stack.
        unsafe { core::ptr::write_volatile(a as *mut u32, PAINT) };
        a += 4;
    }
    bottom
}

/// Bytes of stack used below the caller's frame since [`paint`] returned `bottom`.
pub fn used(bottom: usize) -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let mut a = bottom;
    // SAFETY: reads of the painted region.
    while a < sp && unsafe { core::ptr::read_volatile(a as *const u32) } == PAINT {
        a += 4;
    }
    sp - a
}

/// Exits QEMU with success.
pub fn succeed() -> ! {
    exit(EXIT_SUCCESS);
    halt()
}

/// Exits QEMU with failure.
pub fn fail() -> ! {
    exit(EXIT_FAILURE);
    halt()
}

/// Where execution goes if semihosting's exit returns (no debugger attached).
fn halt() -> ! {
    loop {
        cortex_m::asm::nop();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    fail()
}
