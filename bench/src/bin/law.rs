//! The law's bench in f32 (`twocars_bench::target::law`): `Guidance::decide`, the firmware's path.
#![no_std]
#![no_main]

use twocars_bench::target::law::{run, Prepared};

/// The timed region: one `Guidance::decide`.
#[inline(never)]
fn evaluate(prepared: &mut Prepared<f32>) -> twocars::Decision<f32> {
    let (guidance, p, e) = prepared;
    guidance.decide(p, e)
}

#[cortex_m_rt::entry]
fn main() -> ! {
    run(evaluate)
}
