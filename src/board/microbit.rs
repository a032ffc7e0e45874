//! BBC micro:bit v1 (nRF51822, Cortex-M0 at 16 MHz, no FPU): UART0 on the interface chip's
//! lines (P0.24 TX, P0.25 RX, 115200 8N1), interrupt-driven, and a TIMER0 millisecond clock
//! (the nRF51 has no SysTick). Runs in QEMU's `microbit` machine, which models both.
//!
//! The nRF51 UART signals by events: RXDRDY when a byte is in RXD (its six-byte FIFO refills
//! RXD and raises it again), TXDRDY when the byte written to TXD has left, ERROR with the cause
//! in ERRORSRC (overrun, parity, framing, break). One interrupt line serves all three; TXDRDY's
//! interrupt is enabled only while the transmit queue has bytes.

use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use cortex_m::peripheral::NVIC;
use nrf51_pac::{interrupt, Interrupt, TIMER0, UART0};

use crate::serial::{Board, LoopEnd, RxFlags, UartRegisters};

/// The interface chip's UART lines on micro:bit v1.
const TX_PIN: u32 = 24;
const RX_PIN: u32 = 25;
/// ERRORSRC bits.
const OVERRUN: u32 = 1 << 0;
const PARITY: u32 = 1 << 1;
const FRAMING: u32 = 1 << 2;
const BREAK: u32 = 1 << 3;
/// TIMER0 at 16 MHz / 2^4 = 1 MHz: a compare every 1,000 counts is a millisecond.
const TIMER_PRESCALER: u8 = 4;
const COUNTS_PER_MS: u32 = 1_000;

fn uart() -> &'static nrf51_pac::uart0::RegisterBlock {
    // SAFETY: UART0's register block is valid for the program's life; the loop only writes
    // INTENSET (a set-only register), the handler everything else.
    unsafe { &*UART0::ptr() }
}

fn timer() -> &'static nrf51_pac::timer0::RegisterBlock {
    // SAFETY: TIMER0 is configured once before its interrupt is unmasked, then touched only by
    // its handler.
    unsafe { &*TIMER0::ptr() }
}

/// A byte written to TXD that has not signalled TXDRDY yet (one writer at a time: the handler,
/// or the loop before interrupts start).
static TX_BUSY: AtomicBool = AtomicBool::new(false);

/// UART0's registers as the interrupt handler uses them.
struct Nrf51Uart;

impl UartRegisters for Nrf51Uart {
    fn take_received(&mut self) -> Option<(Option<u8>, RxFlags)> {
        let uart = uart();
        let mut flags = RxFlags::default();
        if uart.events_error.read().bits() != 0 {
            uart.events_error.write(|w| unsafe { w.bits(0) });
            let source = uart.errorsrc.read().bits();
            // Write one to clear.
            uart.errorsrc.write(|w| unsafe { w.bits(source) });
            flags = RxFlags {
                overrun: source & OVERRUN != 0,
                framing: source & (FRAMING | BREAK) != 0,
                noise: false,
                parity: source & PARITY != 0,
            };
        }
        if uart.events_rxdrdy.read().bits() == 0 {
            return (flags != RxFlags::default()).then_some((None, flags));
        }
        // Clear the event first: reading RXD raises it again while the FIFO holds more.
        uart.events_rxdrdy.write(|w| unsafe { w.bits(0) });
        Some((Some(uart.rxd.read().rxd().bits()), flags))
    }

    fn can_transmit(&self) -> bool {
        !TX_BUSY.load(Ordering::Relaxed) || uart().events_txdrdy.read().bits() != 0
    }

    fn transmit(&mut self, byte: u8) {
        let uart = uart();
        uart.events_txdrdy.write(|w| unsafe { w.bits(0) });
        uart.txd.write(|w| unsafe { w.txd().bits(byte) });
        TX_BUSY.store(true, Ordering::Relaxed);
    }

    fn transmit_idle(&mut self) {
        let uart = uart();
        uart.intenclr.write(|w| w.txdrdy().clear());
        uart.events_txdrdy.write(|w| unsafe { w.bits(0) });
        TX_BUSY.store(false, Ordering::Relaxed);
    }
}

/// Enables UART0 with its interrupts and returns the loop's end of its queues; `None` on a
/// second call.
pub fn take_uart() -> Option<LoopEnd<'static>> {
    let line = super::take_line()?;
    let uart = uart();
    uart.pseltxd.write(|w| unsafe { w.bits(TX_PIN) });
    uart.pselrxd.write(|w| unsafe { w.bits(RX_PIN) });
    uart.baudrate.write(|w| w.baudrate().baud115200());
    uart.enable.write(|w| w.enable().enabled());
    uart.intenset
        .write(|w| w.rxdrdy().set_bit().error().set_bit());
    uart.tasks_startrx.write(|w| unsafe { w.bits(1) });
    uart.tasks_starttx.write(|w| unsafe { w.bits(1) });
    // SAFETY: the handler only touches UART0 and the line's interrupt end.
    unsafe { NVIC::unmask(Interrupt::UART0) };
    Some(line)
}

#[interrupt]
fn UART0() {
    super::on_uart_interrupt(&mut Nrf51Uart);
}

static MILLIS: AtomicU32 = AtomicU32::new(0);

/// TIMER0's millisecond clock, and the UART's transmit start.
pub struct Microbit {
    _timer: TIMER0,
}

impl Microbit {
    /// Starts TIMER0 (32-bit, 1 MHz) with a compare interrupt every millisecond.
    pub fn start(timer0: TIMER0) -> Self {
        let t = timer();
        t.bitmode.write(|w| w.bitmode()._32bit());
        t.prescaler
            .write(|w| unsafe { w.prescaler().bits(TIMER_PRESCALER) });
        t.cc[0].write(|w| unsafe { w.bits(COUNTS_PER_MS) });
        t.intenset.write(|w| w.compare0().set());
        t.tasks_clear.write(|w| unsafe { w.bits(1) });
        t.tasks_start.write(|w| unsafe { w.bits(1) });
        // SAFETY: the handler only touches TIMER0 and the millisecond count.
        unsafe { NVIC::unmask(Interrupt::TIMER0) };
        Microbit { _timer: timer0 }
    }
}

impl Board for Microbit {
    fn now_ms(&self) -> u32 {
        MILLIS.load(Ordering::Relaxed)
    }
    fn start_transmit(&self) {
        // TXDRDY's interrupt drains the queue; an idle transmitter is started by pending it.
        uart().intenset.write(|w| w.txdrdy().set_bit());
        NVIC::pend(Interrupt::UART0);
    }
    fn sleep_while(&self, idle: &mut dyn FnMut() -> bool) {
        super::sleep_while(idle);
    }
}

#[interrupt]
fn TIMER0() {
    let t = timer();
    t.events_compare[0].write(|w| unsafe { w.bits(0) });
    // The next compare a millisecond on (the counter runs on; no SHORTS needed).
    let next = t.cc[0].read().bits().wrapping_add(COUNTS_PER_MS);
    t.cc[0].write(|w| unsafe { w.bits(next) });
    // Only this handler writes the count: a load and a store (no atomic add on the M0).
    MILLIS.store(
        MILLIS.load(Ordering::Relaxed).wrapping_add(1),
        Ordering::Relaxed,
    );
}
