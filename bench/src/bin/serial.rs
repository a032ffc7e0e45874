//! The serial loop's bench in f32 (`twocars_bench::target::serial`).
#![no_std]
#![no_main]

use twocars_bench::main_loop::serve_script;
use twocars_bench::target::serial::run;

#[cortex_m_rt::entry]
fn main() -> ! {
    run(&[], serve_script)
}
