//! The law's bench with micromath's f32 functions (`twocars_bench::target::law`): `Guidance::decide`.
#![no_std]
#![no_main]

use twocars_bench::target::law::{run, Prepared};

/// The timed region: one `Guidance::decide`.
#[inline(never)]
fn evaluate(
    prepared: &mut Prepared<twocars::num::micro::Micro>,
) -> twocars::Decision<twocars::num::micro::Micro> {
    let (guidance, p, e) = prepared;
    guidance.decide(p, e)
}

#[cortex_m_rt::entry]
fn main() -> ! {
    run(evaluate)
}
