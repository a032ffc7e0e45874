//! Firmware entry for STM32F405 flight controllers: clocks, USART1, then the guidance loop.
//! A flight build: no log transport; a panic or a serial fault resets the MCU.
#![no_std]
#![no_main]

use stm32f4xx_hal::pac;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::Config;
use stm32f4xx_hal::serial::Serial;
use twocars::board::stm32f405::{Port, SysTickClock};
use twocars::firmware::{serve, Stop};
use twocars::unit::Unit;

/// Core clock, Hz.
const SYSCLK_HZ: u32 = 168_000_000;

#[cortex_m_rt::entry]
fn main() -> ! {
    let (Some(dp), Some(cp)) = (pac::Peripherals::take(), cortex_m::Peripherals::take()) else {
        cortex_m::peripheral::SCB::sys_reset()
    };
    let mut rcc = dp.RCC.freeze(Config::hse(8.MHz()).sysclk(SYSCLK_HZ.Hz()));
    let gpioa = dp.GPIOA.split(&mut rcc);
    let Ok(serial) = Serial::new(dp.USART1, (gpioa.pa9, gpioa.pa10), 115_200.bps(), &mut rcc)
    else {
        cortex_m::peripheral::SCB::sys_reset()
    };
    let clock = SysTickClock::start(cp.SYST, SYSCLK_HZ);
    let mut port = Port::new(serial);
    let mut unit = Unit::new();
    loop {
        match serve(&mut port, &clock, &mut unit) {
            // A flight unit has no session to end: keep serving.
            Stop::Shutdown => {}
            Stop::Serial(_) => cortex_m::peripheral::SCB::sys_reset(),
        }
    }
}

#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
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
