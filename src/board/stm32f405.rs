//! STM32F405 flight controller: USART1 (PA9 TX, PA10 RX, 115200 8N1), interrupt-driven, and a
//! SysTick millisecond clock at 168 MHz from an 8 MHz crystal, or at 16 MHz from the internal
//! oscillator where the crystal or the PLL does not start within a bounded wait ([`clock`]).
//!
//! The HAL configures clocks, pins and the USART; the interrupt handler reads the status and
//! data registers itself, because the HAL's `read` discards the byte that comes with an overrun
//! or a noise flag, and counts faults per byte. USART1's one interrupt line serves RXNE (also
//! raised by an overrun) and TXE (enabled while the transmit queue has bytes).

use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{NVIC, SYST};
use stm32f4xx_hal::pac::{self, interrupt, USART1};
use stm32f4xx_hal::rcc::Rcc;
use stm32f4xx_hal::serial::Serial;

use crate::serial::{Board, LoopEnd, RxFlags, UartRegisters};

fn usart1() -> &'static pac::usart1::RegisterBlock {
    // SAFETY: USART1's register block is valid for the program's life; the handler and the
    // loop touch disjoint bits (the loop only sets TXEIE, inside a critical section).
    unsafe { &*USART1::ptr() }
}

/// USART1's registers as the interrupt handler uses them.
struct Usart1;

impl UartRegisters for Usart1 {
    fn take_received(&mut self) -> Option<(Option<u8>, RxFlags)> {
        let usart = usart1();
        let sr = usart.sr().read();
        let flags = RxFlags {
            overrun: sr.ore().bit_is_set(),
            framing: sr.fe().bit_is_set(),
            noise: sr.nf().bit_is_set(),
            parity: sr.pe().bit_is_set(),
        };
        let full = sr.rxne().bit_is_set();
        if !full && flags == RxFlags::default() {
            return None;
        }
        // Reading DR after SR clears RXNE and every error flag; with an overrun DR still holds
        // the byte received before the lost one.
        let byte = usart.dr().read().dr().bits() as u8;
        Some((full.then_some(byte), flags))
    }

    fn can_transmit(&self) -> bool {
        usart1().sr().read().txe().bit_is_set()
    }

    fn transmit(&mut self, byte: u8) {
        usart1().dr().write(|w| w.dr().set(u16::from(byte)));
    }

    fn transmit_idle(&mut self) {
        // TXE is a level: stop its interrupt until the loop queues more.
        usart1().cr1().modify(|_, w| w.txeie().clear_bit());
    }
}

#[interrupt]
fn USART1() {
    super::on_uart_interrupt(&mut Usart1);
}

/// Takes over a configured USART1: its receive interrupt on, the loop's end of its queues
/// returned (`None` on a second call). The `Serial` stays owned here: its pins stay configured.
pub fn take_uart(serial: Serial<USART1>) -> Option<(Serial<USART1>, LoopEnd<'static>)> {
    let line = super::take_line()?;
    usart1().cr1().modify(|_, w| w.rxneie().set_bit());
    // SAFETY: the handler only touches USART1 and the line's interrupt end.
    unsafe { NVIC::unmask(pac::Interrupt::USART1) };
    Some((serial, line))
}

/// Core clock from the crystal through the PLL, Hz.
pub const SYSCLK_HZ: u32 = 168_000_000;

/// Polls of a ready flag before the start-up gives up on an oscillator or the PLL: at least
/// 6 ms at 16 MHz, where a crystal starts within 2 ms and the PLL locks within 0.1 ms.
const READY_POLLS: u32 = 100_000;

/// The clock the board runs on after its start-up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// The 8 MHz crystal through the PLL: [`SYSCLK_HZ`].
    Crystal,
    /// The internal 16 MHz oscillator without the PLL: the crystal or the PLL did not start.
    Internal,
}

static ON_INTERNAL: AtomicBool = AtomicBool::new(false);

/// The clock [`bring_up`] started.
pub fn clock() -> Clock {
    if ON_INTERNAL.load(Ordering::Relaxed) {
        Clock::Internal
    } else {
        Clock::Crystal
    }
}

/// The board brought up: clocks ([`clock`]), USART1 on PA9/PA10 at 115200 baud with its
/// interrupt ([`take_uart`]), SysTick at 1 kHz, each from the clock actually running. `None` if
/// the peripherals were taken already or the HAL refused the baud rate.
pub fn bring_up() -> Option<(Stm32f405, Serial<USART1>, LoopEnd<'static>)> {
    use stm32f4xx_hal::prelude::*;
    let (dp, cp) = (pac::Peripherals::take()?, cortex_m::Peripherals::take()?);
    let mut rcc = start_clocks(dp.RCC);
    let gpioa = dp.GPIOA.split(&mut rcc);
    let serial = Serial::new(dp.USART1, (gpioa.pa9, gpioa.pa10), 115_200.bps(), &mut rcc).ok()?;
    let board = Stm32f405::start(cp.SYST, rcc.clocks.sysclk().raw());
    let (serial, line) = take_uart(serial)?;
    Some((board, serial, line))
}

/// The crystal and the PLL at [`SYSCLK_HZ`] where both start within [`READY_POLLS`]; the
/// internal oscillator as reset left it otherwise (the HAL's own start-up waits without end).
fn start_clocks(rcc: pac::RCC) -> Rcc {
    use stm32f4xx_hal::prelude::*;
    use stm32f4xx_hal::rcc::{Config, RccExt};
    if crystal_and_pll_start(&rcc) {
        rcc.freeze(Config::hse(8.MHz()).sysclk(SYSCLK_HZ.Hz()))
    } else {
        ON_INTERNAL.store(true, Ordering::Relaxed);
        rcc.constrain()
    }
}

/// Whether `ready` holds within [`READY_POLLS`] polls.
fn within_polls(ready: impl Fn() -> bool) -> bool {
    (0..READY_POLLS).any(|_| ready())
}

/// Starts the crystal and tries the PLL on it (8 MHz / 8 x 336 / 2, the HAL's set-up for
/// 168 MHz), each within a bounded wait; leaves the crystal on and the PLL off for the HAL's
/// start-up where both came, and both off where one did not.
fn crystal_and_pll_start(rcc: &pac::RCC) -> bool {
    rcc.cr().modify(|_, w| w.hseon().set_bit());
    if !within_polls(|| rcc.cr().read().hserdy().bit_is_set()) {
        rcc.cr().modify(|_, w| w.hseon().clear_bit());
        return false;
    }
    // SAFETY: M = 8 and N = 336 are within the fields' documented ranges (2..=63, 50..=432).
    rcc.pllcfgr().modify(|_, w| unsafe {
        w.pllm()
            .bits(8)
            .plln()
            .bits(336)
            .pllp()
            .div2()
            .pllsrc()
            .hse()
    });
    rcc.cr().modify(|_, w| w.pllon().set_bit());
    let locked = within_polls(|| rcc.cr().read().pllrdy().bit_is_set());
    rcc.cr().modify(|_, w| w.pllon().clear_bit());
    let _ = within_polls(|| rcc.cr().read().pllrdy().bit_is_clear());
    if !locked {
        rcc.cr().modify(|_, w| w.hseon().clear_bit());
    }
    locked
}

static MILLIS: AtomicU32 = AtomicU32::new(0);

/// SysTick at 1 kHz on the core clock, and USART1's transmit start.
pub struct Stm32f405 {
    _syst: SYST,
}

impl Stm32f405 {
    /// Starts SysTick with a 1 ms period for a core clock of `core_hz`.
    pub fn start(mut syst: SYST, core_hz: u32) -> Self {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(core_hz / 1000 - 1);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        Stm32f405 { _syst: syst }
    }
}

impl Board for Stm32f405 {
    fn now_ms(&self) -> u32 {
        MILLIS.load(Ordering::Relaxed)
    }
    fn start_transmit(&self) {
        // A read-modify-write of CR1, which the handler also writes: masked.
        cortex_m::interrupt::free(|_| usart1().cr1().modify(|_, w| w.txeie().set_bit()));
        // The handler sends while TXE is set; pended here, it starts where a USART raises no
        // interrupt for TXE (QEMU's model), and on the chip it is one early run.
        NVIC::pend(pac::Interrupt::USART1);
    }
    fn sleep_while(&self, idle: &mut dyn FnMut() -> bool) {
        super::sleep_while(idle);
    }
    fn status_flags(&self) -> u32 {
        match clock() {
            Clock::Crystal => 0,
            Clock::Internal => crate::protocol::message::BOARD_FALLBACK_CLOCK,
        }
    }
}

#[cortex_m_rt::exception]
fn SysTick() {
    MILLIS.fetch_add(1, Ordering::Relaxed);
}
