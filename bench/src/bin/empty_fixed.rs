//! The `law_fixed` image without the law: its ticks are the call overhead, its flash the baseline of the law's.
#![no_std]
#![no_main]

use twocars_bench::target::law::{run, Prepared};

/// The timed region without the law: a safe decision only.
#[inline(never)]
fn evaluate(
    prepared: &mut Prepared<twocars::num::fixed::Fixed>,
) -> twocars::Decision<twocars::num::fixed::Fixed> {
    core::hint::black_box(prepared);
    twocars::Evaluation::safe(twocars::Status::Captured).into()
}

#[cortex_m_rt::entry]
fn main() -> ! {
    run(evaluate)
}
