//! The capture's replay on the target: one line,
//! `replay <ticks> <span ms> <stack bytes> <frames sent> <setpoints> <digest>`.

use cortex_m_semihosting::hprintln;
use twocars::serial::Line;

use super::probe;
use crate::replay::{serve_replay, CAPTURE};

/// Replays the capture the image was built with, prints its line, and exits.
pub fn run() -> ! {
    probe::start();
    let Some(line) = cortex_m::singleton!(: Line = Line::new()) else {
        probe::fail();
    };
    let bottom = probe::paint();
    let r = serve_replay(line, CAPTURE, &probe::now);
    let stack = probe::used(bottom);
    hprintln!(
        "replay {} {} {} {} {} {:08x}",
        r.ticks,
        r.span_ms,
        stack,
        r.frames,
        r.setpoints,
        r.digest
    );
    probe::succeed()
}
