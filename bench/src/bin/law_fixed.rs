//! The law's bench in Q17.14 fixed point (`twocars_bench::target::law`): `Guidance::decide`.
#![no_std]
#![no_main]

use twocars_bench::target::law::{run, Prepared};

/// The timed region: one `Guidance::decide`.
#[inline(never)]
fn evaluate(
    prepared: &mut Prepared<twocars::num::fixed::Fixed>,
) -> twocars::Decision<twocars::num::fixed::Fixed> {
    let (guidance, p, e) = prepared;
    guidance.decide(p, e)
}

#[cortex_m_rt::entry]
fn main() -> ! {
    run(evaluate)
}
