//! The team's bench in fixed point (`twocars_bench::target::team`).
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    twocars_bench::target::team::run::<twocars::Fixed>()
}
