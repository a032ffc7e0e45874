//! The estimator's bench in fixed point (`twocars_bench::target::estimate`).
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    twocars_bench::target::estimate::run::<twocars::Fixed>()
}
