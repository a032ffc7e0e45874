//! QEMU `mps2-an386` (Cortex-M4F): CMSDK UART0, interrupt-driven, and a SysTick millisecond
//! clock.
//!
//! UART0 at 0x4000_4000: DATA +0x0, STATE +0x4 (bit 0 TX full, bit 1 RX full, bit 3 RX overrun,
//! write one to clear), CTRL +0x8 (TX and RX enable, their interrupt enables, RX overrun
//! interrupt enable), INTSTATUS/INTCLEAR +0xC (write one to clear). Its interrupts: RX on NVIC
//! line 0, TX on 1 (raised each time a byte leaves the TX register), the UARTs' overruns ORed on
//! 12. The CMSDK UART has no framing or parity detection; QEMU never overruns it (its character
//! backend waits), real silicon can. No baud divisor is needed in emulation.

use core::ptr::{read_volatile, write_volatile};
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{NVIC, SYST};

use crate::serial::{Board, LoopEnd, RxFlags, UartRegisters};

const UART0: usize = 0x4000_4000;
const DATA: usize = 0x0;
const STATE: usize = 0x4;
const CTRL: usize = 0x8;
const INTCLEAR: usize = 0xC;
const TX_FULL: u32 = 1 << 0;
const RX_FULL: u32 = 1 << 1;
const RX_OVERRUN: u32 = 1 << 3;
const TX_ENABLE: u32 = 1 << 0;
const RX_ENABLE: u32 = 1 << 1;
const TX_INTERRUPT_ENABLE: u32 = 1 << 2;
const RX_INTERRUPT_ENABLE: u32 = 1 << 3;
const RX_OVERRUN_INTERRUPT_ENABLE: u32 = 1 << 5;
const TX_INTERRUPT: u32 = 1 << 0;
const RX_INTERRUPT: u32 = 1 << 1;
/// NVIC lines of UART0 on mps2-an385/an386: receive, transmit, and the UARTs' overruns.
const UART0_RX_IRQ: u16 = 0;
const UART0_TX_IRQ: u16 = 1;
const UART_OVERRUN_IRQ: u16 = 12;
/// SysTick runs on the 25 MHz processor clock.
const CORE_HZ: u32 = 25_000_000;

fn reg(offset: usize) -> *mut u32 {
    (UART0 + offset) as *mut u32
}

fn read(offset: usize) -> u32 {
    // SAFETY: a register of UART0, a valid MMIO block on mps2-an386.
    unsafe { read_volatile(reg(offset)) }
}

fn write(offset: usize, value: u32) {
    // SAFETY: as above; every write below is one the CMSDK UART documents.
    unsafe { write_volatile(reg(offset), value) }
}

/// UART0's registers as the interrupt handler uses them.
struct Cmsdk;

impl UartRegisters for Cmsdk {
    fn take_received(&mut self) -> Option<(Option<u8>, RxFlags)> {
        let state = read(STATE);
        let flags = RxFlags {
            overrun: state & RX_OVERRUN != 0,
            ..RxFlags::default()
        };
        if flags.overrun {
            write(STATE, RX_OVERRUN);
        }
        if state & RX_FULL == 0 {
            return flags.overrun.then_some((None, flags));
        }
        // Acknowledge first: a byte landing after the read raises the interrupt again.
        write(INTCLEAR, RX_INTERRUPT);
        // Only the low 8 bits carry data.
        Some((Some(read(DATA) as u8), flags))
    }

    fn can_transmit(&self) -> bool {
        read(STATE) & TX_FULL == 0
    }

    fn transmit(&mut self, byte: u8) {
        // Acknowledge the last byte's interrupt; this byte raises the next one.
        write(INTCLEAR, TX_INTERRUPT);
        write(DATA, u32::from(byte));
    }

    fn transmit_idle(&mut self) {
        write(INTCLEAR, TX_INTERRUPT);
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

/// Enables UART0 with its interrupts and returns the loop's end of its queues; `None` on a
/// second call.
pub fn take_uart() -> Option<LoopEnd<'static>> {
    let line = super::take_line()?;
    write(
        CTRL,
        TX_ENABLE
            | RX_ENABLE
            | TX_INTERRUPT_ENABLE
            | RX_INTERRUPT_ENABLE
            | RX_OVERRUN_INTERRUPT_ENABLE,
    );
    for irq in [UART0_RX_IRQ, UART0_TX_IRQ, UART_OVERRUN_IRQ] {
        // SAFETY: the handler below only touches UART0 and the line's interrupt end.
        unsafe { NVIC::unmask(Irq(irq)) };
    }
    Some(line)
}

/// Every device interrupt lands here (no device crate): the UART's lines run the shared
/// handler; any other line has nothing to do.
#[cortex_m_rt::exception]
unsafe fn DefaultHandler(_irqn: i16) {
    super::on_uart_interrupt(&mut Cmsdk);
}

static MILLIS: AtomicU32 = AtomicU32::new(0);

/// SysTick at 1 kHz on the processor clock, and the UART's transmit start.
pub struct Mps2 {
    _syst: SYST,
}

impl Mps2 {
    /// Starts SysTick with a 1 ms period and its interrupt.
    pub fn start(mut syst: SYST) -> Self {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(CORE_HZ / 1000 - 1);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        Mps2 { _syst: syst }
    }
}

impl Board for Mps2 {
    fn now_ms(&self) -> u32 {
        MILLIS.load(Ordering::Relaxed)
    }
    fn start_transmit(&self) {
        // The TX interrupt fires per byte sent; an idle transmitter is started by pending it.
        NVIC::pend(Irq(UART0_TX_IRQ));
    }
    fn sleep_while(&self, idle: &mut dyn FnMut() -> bool) {
        super::sleep_while(idle);
    }
}

#[cortex_m_rt::exception]
fn SysTick() {
    MILLIS.fetch_add(1, Ordering::Relaxed);
}
