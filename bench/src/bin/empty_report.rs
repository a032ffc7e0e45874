//! The `law_report` image without the law: its ticks are the call overhead, its flash the baseline of the law's.
#![no_std]
#![no_main]

use twocars_bench::target::law::{run, Prepared};

/// The timed region without the law: a safe evaluation only.
#[inline(never)]
fn evaluate(prepared: &mut Prepared<f32>) -> twocars::Evaluation<f32> {
    core::hint::black_box(prepared);
    twocars::Evaluation::safe(twocars::Status::Captured)
}

#[cortex_m_rt::entry]
fn main() -> ! {
    run(evaluate)
}
