//! The value table's bench (`twocars_bench::target::table`).
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    twocars_bench::target::table::run()
}
