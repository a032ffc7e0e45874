//! The serial loop's bench with the value tables (`twocars_bench::target::serial`): the unit
//! carries `table.tcv` and the session plays it (Configure policy 2).
#![no_std]
#![no_main]

use twocars_bench::main_loop::serve_script;
use twocars_bench::target::{probe, serial, table};

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(set) = table::tables() else {
        probe::fail();
    };
    serial::run(core::slice::from_ref(set), serve_script)
}
