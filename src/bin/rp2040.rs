//! Firmware entry for the Raspberry Pi Pico (RP2040, Cortex-M0+, no FPU): the board started
//! (125 MHz from the 12 MHz crystal, UART0 on GP0/GP1 at 115200 8N1), then the guidance loop
//! with the fixed-point (Q17.14) law. Flash it as a UF2 (`elf2uf2-rs`) or over SWD; rp2040js
//! runs it too (`cargo xtask run --board rp2040`).
#![no_std]
#![no_main]

use twocars::board::rp2040::Pico;
use twocars::num::fixed::Fixed;
use twocars::protocol::endpoint::Endpoint;
use twocars::serial::serve_to_shutdown;

/// The second-stage bootloader for the Pico's W25Q080 flash, first in flash (src/board/rp2040.x).
#[link_section = ".boot2"]
#[used]
pub static BOOT2_FIRMWARE: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(peripherals) = rp2040_pac::Peripherals::take() else {
        halt()
    };
    let Some((board, mut line)) = Pico::start(peripherals) else {
        halt()
    };
    let mut unit = Endpoint::<Fixed>::new();
    serve_to_shutdown(&mut line, &board, &mut unit);
    halt()
}

/// Sleeps for good (a failed start, or after Shutdown: the host power-cycles the unit).
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

// The flight build (`panic-never`) takes the board module's link-time check instead.
#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    halt()
}
