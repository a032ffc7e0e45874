//! The law's bench in f32 with the per-pair report (`twocars_bench::target::law`): `Guidance::step`.
#![no_std]
#![no_main]

use twocars_bench::target::law::{run, Prepared};

/// The timed region: one `Guidance::step` with its report.
#[inline(never)]
fn evaluate(prepared: &mut Prepared<f32>) -> twocars::Evaluation<f32> {
    let (guidance, p, e) = prepared;
    guidance.step(p, e)
}

#[cortex_m_rt::entry]
fn main() -> ! {
    run(evaluate)
}
