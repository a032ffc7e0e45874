//! QEMU `mps2-an386` (Cortex-M4F): CMSDK UART0 and a SysTick millisecond clock.
//!
//! UART0 at 0x4000_4000: DATA +0x0, STATE +0x4 (bit 0 TX full, bit 1 RX full), CTRL +0x8
//! (bit 0 TX enable, bit 1 RX enable). TX is enabled before the first write: in QEMU a write with
//! TX disabled latches TX-full for good. No baud divisor is needed in emulation.

use core::convert::Infallible;
use core::ptr::{read_volatile, write_volatile};
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;

use crate::firmware::Clock;

const UART0: usize = 0x4000_4000;
const DATA: usize = 0x0;
const STATE: usize = 0x4;
const CTRL: usize = 0x8;
const TX_FULL: u32 = 1 << 0;
const RX_FULL: u32 = 1 << 1;
const INTCLEAR: usize = 0xC;
const TX_ENABLE: u32 = 1 << 0;
const RX_ENABLE: u32 = 1 << 1;
const RX_INTERRUPT_ENABLE: u32 = 1 << 3;
const RX_INTERRUPT: u32 = 1 << 1;
/// NVIC line of UART0's receive interrupt on mps2-an385/an386.
const UART0_RX_IRQ: u16 = 0;
/// SysTick runs on the 25 MHz processor clock.
const CORE_HZ: u32 = 25_000_000;

/// CMSDK UART0, owned once.
pub struct Uart {
    _private: (),
}

fn reg(offset: usize) -> *mut u32 {
    (UART0 + offset) as *mut u32
}

impl Uart {
    /// Enables TX and RX.
    ///
    /// # Safety
    /// Call once: the returned value owns UART0's registers.
    pub unsafe fn take() -> Self {
        // SAFETY: UART0 is a valid MMIO block on mps2-an386; the caller owns it.
        unsafe { write_volatile(reg(CTRL), TX_ENABLE | RX_ENABLE | RX_INTERRUPT_ENABLE) };
        // SAFETY: the handler below only clears UART0's interrupt flag; no shared state.
        unsafe { cortex_m::peripheral::NVIC::unmask(Irq(UART0_RX_IRQ)) };
        Uart { _private: () }
    }

    fn state(&self) -> u32 {
        // SAFETY: STATE is a readable register of the owned UART.
        unsafe { read_volatile(reg(STATE)) }
    }
}

impl embedded_io::ErrorType for Uart {
    type Error = Infallible;
}

impl embedded_io::ReadReady for Uart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(self.state() & RX_FULL != 0)
    }
}

impl embedded_io::Read for Uart {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let Some(first) = buf.first_mut() else {
            return Ok(0);
        };
        while self.state() & RX_FULL == 0 {}
        // SAFETY: DATA is readable; RX holds a byte. Only the low 8 bits carry data.
        *first = unsafe { read_volatile(reg(DATA)) } as u8;
        Ok(1)
    }
}

impl embedded_io::Write for Uart {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for &byte in buf {
            while self.state() & TX_FULL != 0 {}
            // SAFETY: DATA is writable; TX has room.
            unsafe { write_volatile(reg(DATA), u32::from(byte)) };
        }
        Ok(buf.len())
    }
    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// An NVIC interrupt line number (there is no device crate for mps2-an386).
#[derive(Clone, Copy)]
struct Irq(u16);

// SAFETY: the line numbers used are valid interrupt numbers of the board.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self.0
    }
}

/// Every device interrupt lands here: clear UART0's receive flag; the main loop reads the byte.
#[cortex_m_rt::exception]
unsafe fn DefaultHandler(_irqn: i16) {
    // SAFETY: INTCLEAR is a write-one-to-clear register of UART0.
    unsafe { write_volatile(reg(INTCLEAR), RX_INTERRUPT) };
}

static MILLIS: AtomicU32 = AtomicU32::new(0);

/// SysTick at 1 kHz on the processor clock.
pub struct SysTickClock {
    _syst: SYST,
}

impl SysTickClock {
    /// Starts SysTick with a 1 ms period and its interrupt.
    pub fn start(mut syst: SYST) -> Self {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(CORE_HZ / 1000 - 1);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        SysTickClock { _syst: syst }
    }
}

impl Clock for SysTickClock {
    fn now_ms(&self) -> u32 {
        MILLIS.load(Ordering::Relaxed)
    }
    fn wait_for_event(&self) {
        cortex_m::asm::wfi();
    }
}

#[cortex_m_rt::exception]
fn SysTick() {
    MILLIS.fetch_add(1, Ordering::Relaxed);
}
