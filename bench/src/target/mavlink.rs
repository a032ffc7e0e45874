//! The MAVLink endpoint's bench on the target: the sessions of [`crate::mavlink`] (empty,
//! ignored positions, guided; unsigned and signed) served by the endpoint's serial path, one
//! line per session: `mavlink <index in SESSIONS> <ticks> <stack bytes> <frames sent> <digest>`.

use core::hint::black_box;

use cortex_m_semihosting::hprintln;
use twocars::serial::Line;

use super::probe;
use crate::mavlink::{script, serve_script, SCRIPT_CAPACITY, SESSIONS};

/// Serves each session, printing one `mavlink` line each, and exits.
pub fn run() -> ! {
    probe::start();
    let mut bytes = [0u8; SCRIPT_CAPACITY];
    let Some(line) = cortex_m::singleton!(: Line = Line::new()) else {
        probe::fail();
    };
    for (i, (session, signed)) in SESSIONS.into_iter().enumerate() {
        let Some(script) = script(session, signed, &mut bytes).and_then(|n| bytes.get(..n)) else {
            hprintln!("script does not fit");
            continue;
        };
        let bottom = probe::paint();
        let start = probe::now();
        let outcome = serve_script(line, black_box(script), signed);
        let ticks = probe::ticks_since(start);
        let stack = probe::used(bottom);
        hprintln!(
            "mavlink {} {} {} {} {:08x}",
            i,
            ticks,
            stack,
            outcome.frames,
            outcome.digest
        );
    }
    probe::succeed()
}
