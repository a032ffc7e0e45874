//! The MAVLink endpoint's bench (`twocars_bench::target::mavlink`).
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    twocars_bench::target::mavlink::run()
}
