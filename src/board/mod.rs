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

#[cfg(feature = "firmware-microbit")]
pub mod microbit;

#[cfg(feature = "firmware-rp2040")]
pub mod rp2040;

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
