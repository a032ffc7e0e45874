//! The MAVLink endpoint's bench on the target: the sessions of [`crate::mavlink`] (empty,
//! ignored positions, guided) served by the endpoint's serial path, one line per session:
//! `mavlink <session> <ticks> <stack bytes> <frames sent> <digest>`.

use core::hint::black_box;

use cortex_m_semihosting::hprintln;
use twocars::serial::Line;

use super::probe;
use crate::mavlink::{script, serve_script, Session, SCRIPT_CAPACITY};

/// Serves each session, printing one `mavlink` line each, and exits.
pub fn run() -> ! {
    probe::start();
    let mut bytes = [0u8; SCRIPT_CAPACITY];
    let Some(line) = cortex_m::singleton!(: Line = Line::new()) else {
        probe::fail();
    };
    for (i, session) in [Session::Empty, Session::Ignored, Session::Guided]
        .into_iter()
        .enumerate()
    {
        let Some(script) = script(session, &mut bytes).and_then(|n| bytes.get(..n)) else {
            hprintln!("script does not fit");
            continue;
        };
        let bottom = probe::paint();
        let start = probe::now();
        let outcome = serve_script(line, black_box(script));
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
