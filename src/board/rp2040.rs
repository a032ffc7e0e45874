//! Raspberry Pi Pico (RP2040, Cortex-M0+ at 125 MHz, no FPU): clocks from the 12 MHz crystal,
//! UART0 on GP0 (TX) and GP1 (RX), 115200 8N1, interrupt-driven, and the RP2040's 1 MHz TIMER as
//! the millisecond clock, its ALARM0 waking the loop every millisecond so that the watchdog
//! runs through the host's silences. The image runs in rp2040js (`cargo xtask run --board rp2040`); it has
//! not run on a board yet.
//!
//! Set up with the PAC's registers, in the RP2040 datasheet's order (the pico-sdk's
//! `clocks_init`). `rp2040-hal` does the same, but its clock and baud-rate set-up divide by
//! frequencies known only at run time, so its image cannot be proven panic-free at link time
//! (`rp2040_hal::clocks::fractional_div`'s division by zero, the UART's divisor check); here
//! every divisor is a constant.
//!
//! The interrupt handler reads the PL011's registers: each byte comes with its own fault flags
//! in the data register (framing, parity, break, overrun). The FIFOs stay on: the receive
//! interrupt fires at the FIFO's watermark and the receive timeout after 32 bit times of
//! silence; the transmit interrupt (enabled while the transmit queue has bytes) when the
//! transmit FIFO drains to its watermark.

use cortex_m::peripheral::NVIC;
use rp2040_pac::{self as pac, interrupt, Interrupt, TIMER, UART0};

use crate::serial::{Board, LoopEnd, RxFlags, UartRegisters};

/// The Pico's crystal, Hz.
const XOSC_HZ: u32 = 12_000_000;
/// PLL_SYS: 12 MHz x 125 = 1,500 MHz VCO, / 6 / 2 = 125 MHz, the system and peripheral clock.
const PLL_FBDIV: u32 = 125;
const PLL_POSTDIV1: u32 = 6;
const PLL_POSTDIV2: u32 = 2;
const SYS_HZ: u32 = XOSC_HZ / 1_000_000 * PLL_FBDIV / PLL_POSTDIV1 / PLL_POSTDIV2 * 1_000_000;
/// PL011 divisor for 115200 baud from the 125 MHz peripheral clock, as the datasheet forms it:
/// 8 clk / baud in 1/128 steps, integer part and a rounded 6-bit fraction (115,207 baud).
const BAUD: u32 = 115_200;
const BAUD_DIV: u32 = 8 * SYS_HZ / BAUD;
const UART_IBRD: u32 = BAUD_DIV >> 7;
const UART_FBRD: u32 = (BAUD_DIV & 0x7f).div_ceil(2);

/// RESETS bits of the blocks used.
const RESET_IO_BANK0: u32 = 1 << 5;
const RESET_PADS_BANK0: u32 = 1 << 8;
const RESET_PLL_SYS: u32 = 1 << 12;
const RESET_TIMER: u32 = 1 << 21;
const RESET_UART0: u32 = 1 << 22;

/// The loop's wake-up period, TIMER microseconds.
const WAKE_US: u32 = 1_000;
/// TIMER's INTR / INTE bit of ALARM0.
const ALARM0: u32 = 1 << 0;

/// UARTDR's flags beside the byte.
const FRAMING: u32 = 1 << 8;
const PARITY: u32 = 1 << 9;
const BREAK: u32 = 1 << 10;
const OVERRUN: u32 = 1 << 11;
/// UARTFR: receive FIFO empty, transmit FIFO full.
const RX_EMPTY: u32 = 1 << 4;
const TX_FULL: u32 = 1 << 5;
/// UARTIMSC / UARTICR: receive, transmit, receive timeout.
const RX_INTERRUPT: u32 = 1 << 4;
const TX_INTERRUPT: u32 = 1 << 5;
const RX_TIMEOUT_INTERRUPT: u32 = 1 << 6;

/// Takes the blocks in `mask` out of reset and waits until they are.
fn unreset(resets: &pac::RESETS, mask: u32) {
    resets
        .reset()
        .modify(|r, w| unsafe { w.bits(r.bits() & !mask) });
    while resets.reset_done().read().bits() & mask != mask {}
}

/// Crystal, PLL_SYS at 125 MHz, clk_ref from the crystal, clk_sys and clk_peri from the PLL, and
/// the watchdog's 1 us tick that the TIMER counts (the pico-sdk's order).
fn start_clocks(p: &pac::Peripherals) {
    let clocks = &p.CLOCKS;
    clocks.clk_sys_resus_ctrl().write(|w| unsafe { w.bits(0) });
    // Crystal: 1-15 MHz range, about 1 ms of start-up (in 256-cycle steps), enabled.
    p.XOSC
        .startup()
        .write(|w| unsafe { w.bits((XOSC_HZ / 1000 + 128) / 256) });
    p.XOSC
        .ctrl()
        .write(|w| unsafe { w.bits((0xfab << 12) | 0xaa0) });
    while p.XOSC.status().read().bits() & (1 << 31) == 0 {}
    // Off the auxiliary sources before the PLL changes: clk_sys from clk_ref, clk_ref from ROSC.
    clocks
        .clk_sys_ctrl()
        .modify(|r, w| unsafe { w.bits(r.bits() & !1) });
    while clocks.clk_sys_selected().read().bits() != 1 {}
    clocks
        .clk_ref_ctrl()
        .modify(|r, w| unsafe { w.bits(r.bits() & !3) });
    while clocks.clk_ref_selected().read().bits() != 1 {}
    // PLL_SYS from reset: reference divider 1, feedback 125, powered up, locked, post-dividers.
    p.RESETS
        .reset()
        .modify(|r, w| unsafe { w.bits(r.bits() | RESET_PLL_SYS) });
    unreset(&p.RESETS, RESET_PLL_SYS);
    let pll = &p.PLL_SYS;
    pll.cs().write(|w| unsafe { w.bits(1) });
    pll.fbdiv_int().write(|w| unsafe { w.bits(PLL_FBDIV) });
    // PWR: clear PD (bit 0) and VCOPD (bit 5).
    pll.pwr()
        .modify(|r, w| unsafe { w.bits(r.bits() & !(1 | (1 << 5))) });
    while pll.cs().read().bits() & (1 << 31) == 0 {}
    pll.prim()
        .write(|w| unsafe { w.bits((PLL_POSTDIV1 << 16) | (PLL_POSTDIV2 << 12)) });
    // POSTDIVPD (bit 3).
    pll.pwr()
        .modify(|r, w| unsafe { w.bits(r.bits() & !(1 << 3)) });
    // clk_ref from the crystal, divided by 1.
    clocks.clk_ref_div().write(|w| unsafe { w.bits(1 << 8) });
    clocks
        .clk_ref_ctrl()
        .modify(|r, w| unsafe { w.bits((r.bits() & !3) | 2) });
    while clocks.clk_ref_selected().read().bits() != 1 << 2 {}
    // clk_sys from PLL_SYS (auxiliary source 0), divided by 1, glitchless switch to it.
    clocks.clk_sys_div().write(|w| unsafe { w.bits(1 << 8) });
    clocks
        .clk_sys_ctrl()
        .modify(|r, w| unsafe { w.bits(r.bits() & !(7 << 5)) });
    clocks
        .clk_sys_ctrl()
        .modify(|r, w| unsafe { w.bits(r.bits() | 1) });
    while clocks.clk_sys_selected().read().bits() != 1 << 1 {}
    // clk_peri from clk_sys (auxiliary source 0), enabled (bit 11).
    clocks.clk_peri_ctrl().write(|w| unsafe { w.bits(0) });
    clocks.clk_peri_ctrl().write(|w| unsafe { w.bits(1 << 11) });
    // The watchdog's tick: enabled (bit 9), one per microsecond of the 12 MHz clk_ref.
    p.WATCHDOG
        .tick()
        .write(|w| unsafe { w.bits((1 << 9) | (XOSC_HZ / 1_000_000)) });
}

fn uart() -> &'static pac::uart0::RegisterBlock {
    // SAFETY: UART0's register block is valid for the program's life; UARTIMSC is changed only
    // in critical sections (the handler runs in one), everything else only by the handler.
    unsafe { &*UART0::ptr() }
}

/// UART0's registers as the interrupt handler uses them.
struct Pl011;

impl UartRegisters for Pl011 {
    fn take_received(&mut self) -> Option<(Option<u8>, RxFlags)> {
        let uart = uart();
        if uart.uartfr().read().bits() & RX_EMPTY != 0 {
            return None;
        }
        let word = uart.uartdr().read().bits();
        let flags = RxFlags {
            overrun: word & OVERRUN != 0,
            framing: word & (FRAMING | BREAK) != 0,
            noise: false,
            parity: word & PARITY != 0,
        };
        // Only the low 8 bits carry data.
        Some((Some(word as u8), flags))
    }

    fn can_transmit(&self) -> bool {
        uart().uartfr().read().bits() & TX_FULL == 0
    }

    fn transmit(&mut self, byte: u8) {
        uart()
            .uartdr()
            .write(|w| unsafe { w.bits(u32::from(byte)) });
    }

    fn transmit_idle(&mut self) {
        let uart = uart();
        uart.uartimsc()
            .modify(|r, w| unsafe { w.bits(r.bits() & !TX_INTERRUPT) });
        uart.uarticr().write(|w| unsafe { w.bits(TX_INTERRUPT) });
    }
}

#[interrupt]
fn UART0_IRQ() {
    super::on_uart_interrupt(&mut Pl011);
}

/// Arms ALARM0 a wake-up period after the TIMER's count now (an alarm matches the low 32
/// bits exactly, so it is set from the count, never from the last target, which may have
/// passed).
fn arm_wake_up() {
    // SAFETY: ALARM0, INTR and INTE are written only here and at start, before the
    // interrupt is unmasked.
    let timer = unsafe { &*TIMER::ptr() };
    let now = timer.timerawl().read().bits();
    timer
        .alarm0()
        .write(|w| unsafe { w.bits(now.wrapping_add(WAKE_US)) });
}

/// ALARM0: clears the alarm and arms the next. Its work is to wake the loop from `wfi`.
#[interrupt]
fn TIMER_IRQ_0() {
    // SAFETY: as in `arm_wake_up`.
    let timer = unsafe { &*TIMER::ptr() };
    timer.intr().write(|w| unsafe { w.bits(ALARM0) });
    arm_wake_up();
}

/// The Pico's clocks, pins, UART0 and TIMER, started.
pub struct Pico {
    timer: pac::TIMER,
}

impl Pico {
    /// Starts the clocks, takes UART0, the TIMER and the IO and pad banks out of reset, routes
    /// GP0 and GP1 to UART0 and enables it (8N1, FIFOs on) with its receive interrupts, and arms
    /// ALARM0's millisecond wake-up; returns the board and the loop's end of the UART's queues
    /// (`None` on a second call).
    pub fn start(p: pac::Peripherals) -> Option<(Self, LoopEnd<'static>)> {
        start_clocks(&p);
        unreset(
            &p.RESETS,
            RESET_IO_BANK0 | RESET_PADS_BANK0 | RESET_TIMER | RESET_UART0,
        );
        // GP0 and GP1: function 2, UART0 (the pads' reset state keeps GP1's input enabled).
        // (Constant indices: a loop over them kept the PAC's bounds check, a panic path.)
        p.IO_BANK0
            .gpio(0)
            .gpio_ctrl()
            .write(|w| unsafe { w.bits(2) });
        p.IO_BANK0
            .gpio(1)
            .gpio_ctrl()
            .write(|w| unsafe { w.bits(2) });
        let line = super::take_line()?;
        let uart = &p.UART0;
        uart.uartibrd().write(|w| unsafe { w.bits(UART_IBRD) });
        uart.uartfbrd().write(|w| unsafe { w.bits(UART_FBRD) });
        // 8 data bits (WLEN = 3), FIFOs on (FEN); this write latches the divisor.
        uart.uartlcr_h()
            .write(|w| unsafe { w.bits((3 << 5) | (1 << 4)) });
        // UARTEN, TXE, RXE.
        uart.uartcr()
            .write(|w| unsafe { w.bits(1 | (1 << 8) | (1 << 9)) });
        cortex_m::interrupt::free(|_| {
            uart.uartimsc()
                .write(|w| unsafe { w.bits(RX_INTERRUPT | RX_TIMEOUT_INTERRUPT) });
        });
        // SAFETY: the handler only touches UART0 and the line's interrupt end.
        unsafe { NVIC::unmask(Interrupt::UART0_IRQ) };
        p.TIMER.inte().write(|w| unsafe { w.bits(ALARM0) });
        arm_wake_up();
        // SAFETY: the handler only touches ALARM0 and its interrupt flag.
        unsafe { NVIC::unmask(Interrupt::TIMER_IRQ_0) };
        Some((Pico { timer: p.TIMER }, line))
    }
}

impl Board for Pico {
    fn now_ms(&self) -> u32 {
        // The 64-bit microsecond count read high, low, high (a carry between the reads retries).
        let t = &self.timer;
        let micros = loop {
            let high = t.timerawh().read().bits();
            let low = t.timerawl().read().bits();
            if t.timerawh().read().bits() == high {
                break (u64::from(high) << 32) | u64::from(low);
            }
        };
        // Milliseconds, wrapping at 2^32 like every board's clock.
        (micros / 1_000) as u32
    }
    fn start_transmit(&self) {
        cortex_m::interrupt::free(|_| {
            uart()
                .uartimsc()
                .modify(|r, w| unsafe { w.bits(r.bits() | TX_INTERRUPT) });
        });
        // The transmit interrupt fires on the FIFO draining past its watermark: pend it to
        // start an idle transmitter.
        NVIC::pend(Interrupt::UART0_IRQ);
    }
    fn sleep_while(&self, idle: &mut dyn FnMut() -> bool) {
        super::sleep_while(idle);
    }
}
