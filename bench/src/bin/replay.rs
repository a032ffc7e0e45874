//! A captured MAVLink stream through the endpoint's serial path
//! (`twocars_bench::target::replay`).
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    twocars_bench::target::replay::run()
}
