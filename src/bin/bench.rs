//! Bench firmware: times one full evaluation of the law (both roles, four tangents, the game,
//! the sampled commands: `Guidance::step`) per bench state with SysTick on the processor clock,
//! under QEMU `-icount` so ticks count instructions; paints the stack to find the law's peak
//! use. Prints `state <i> <ticks> <stack bytes>` lines over semihosting, then exits.
//! With `bench-empty` the law is replaced by nothing: its ticks are the call overhead, its image
//! the baseline of the law's flash.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_semihosting::debug::{exit, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::hprintln;
use twocars::bench::STATES;

const PAINT: u32 = 0xA5A5_5A5A;
/// Bytes of stack painted below the caller's frame.
const PAINT_BYTES: usize = 4096;

#[inline(never)]
fn evaluate(i: usize) -> f32 {
    let Some(&(p, e)) = STATES.get(black_box(i)) else {
        return 0.0;
    };
    #[cfg(feature = "bench-empty")]
    {
        black_box((p, e));
        0.0
    }
    #[cfg(not(feature = "bench-empty"))]
    {
        let [v_pm, w_pm, v_em, w_em] = black_box(twocars::bench::LIMITS);
        let Ok(limits) = twocars::Limits::<f32>::new(v_pm, w_pm, v_em, w_em) else {
            return -1.0;
        };
        let law = twocars::Law::new(limits, twocars::Variant::Paper);
        let Ok(mut guidance) = twocars::Guidance::new(law, twocars::bench::DT) else {
            return -1.0;
        };
        let (Ok(p), Ok(e)) = (
            twocars::VehicleState::new(p[0], p[1], p[2]),
            twocars::VehicleState::new(e[0], e[1], e[2]),
        ) else {
            return -1.0;
        };
        let ev = guidance.step(&p, &e);
        ev.command.pursuer + ev.command.evader
    }
}

fn paint() -> usize {
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

fn used(bottom: usize) -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let mut a = bottom;
    // SAFETY: reads of the painted region.
    while a < sp && unsafe { core::ptr::read_volatile(a as *const u32) } == PAINT {
        a += 4;
    }
    sp - a
}

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        exit(EXIT_FAILURE);
        loop {
            cortex_m::asm::nop();
        }
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00FF_FFFF);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();
    for i in 0..STATES.len() {
        let bottom = paint();
        let start = cortex_m::peripheral::SYST::get_current();
        let out = evaluate(i);
        let end = cortex_m::peripheral::SYST::get_current();
        black_box(out);
        let stack = used(bottom);
        // SysTick counts down, 24 bits.
        let ticks = start.wrapping_sub(end) & 0x00FF_FFFF;
        hprintln!("state {} {} {}", i, ticks, stack);
    }
    exit(EXIT_SUCCESS);
    loop {
        cortex_m::asm::nop();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::nop();
    }
}
