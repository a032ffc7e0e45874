//! Board shells: registers and clocks only; the loop is [`crate::serial::serve`], the UART's
//! interrupt [`crate::serial::InterruptEnd::on_interrupt`].
#![allow(unsafe_code)]

use core::cell::RefCell;

use cortex_m::interrupt::Mutex;

use crate::serial::{InterruptEnd, Line, LoopEnd, UartRegisters};

#[cfg(feature = "board-qemu")]
pub mod qemu_mps2;

#[cfg(feature = "board-stm32f405")]
pub mod stm32f405;

#[cfg(feature = "board-microbit")]
pub mod microbit;

#[cfg(feature = "board-rp2040")]
pub mod rp2040;

#[cfg(feature = "tables-in-flash")]
pub mod tables;

/// The UART interrupt's end of the board's one [`Line`], handed over by [`take_line`].
static INTERRUPT_END: Mutex<RefCell<Option<InterruptEnd<'static>>>> =
    Mutex::new(RefCell::new(None));

/// The board's [`Line`], split once: its interrupt end is kept for [`on_uart_interrupt`], its
/// loop end returned. `None` on a second call.
fn take_line() -> Option<LoopEnd<'static>> {
    let line = cortex_m::singleton!(: Line = Line::new())?;
    let (interrupt, main) = line.split();
    cortex_m::interrupt::free(|cs| {
        // `try_borrow_mut`: no panic path (nothing else borrows it before this returns).
        let mut end = INTERRUPT_END.borrow(cs).try_borrow_mut().ok()?;
        *end = Some(interrupt);
        Some(main)
    })
}

/// The body of a board's UART interrupt handler.
fn on_uart_interrupt<U: UartRegisters>(uart: &mut U) {
    cortex_m::interrupt::free(|cs| {
        // `try_borrow_mut`: no panic path (the handler does not nest, so it never fails).
        if let Ok(mut end) = INTERRUPT_END.borrow(cs).try_borrow_mut() {
            if let Some(end) = end.as_mut() {
                end.on_interrupt(uart);
            }
        }
    });
}

/// Sleeps until an interrupt while `idle()` holds; checked with interrupts masked (WFI still
/// wakes on a pending one), so an interrupt between the check and the sleep is not missed.
fn sleep_while(idle: &mut dyn FnMut() -> bool) {
    cortex_m::interrupt::free(|_| {
        if idle() {
            cortex_m::asm::wfi();
        }
    });
}

/// The flight images' panic handler (`panic-never`, every board): it calls a symbol defined
/// nowhere, so an image with any reachable panic path fails to link (docs/reliability.md).
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

/// Ends a QEMU session with `code` over semihosting (0 after Shutdown, 1 on a failed start or a
/// panic); sleeps for good if the exit returns (not under QEMU).
#[cfg(any(feature = "board-qemu", feature = "board-microbit"))]
pub fn exit_qemu(code: cortex_m_semihosting::debug::ExitStatus) -> ! {
    cortex_m_semihosting::debug::exit(code);
    loop {
        cortex_m::asm::wfi();
    }
}
