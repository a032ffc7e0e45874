//! The serial loop's bench in Q17.14 fixed point (`twocars_bench::target::serial`): the wire's
//! f32 values converted with integers only.
#![no_std]
#![no_main]

use twocars_bench::main_loop::serve_script_fixed;
use twocars_bench::target::serial::run;

#[cortex_m_rt::entry]
fn main() -> ! {
    run(&[], |line, script, _| serve_script_fixed(line, script))
}
