//! The serial loop's bench on the target: the session of [`crate::main_loop`] served by the
//! firmware's serial path (the UART interrupt's handler and `twocars::serial::service` over the
//! queues, fed by a scripted UART), with and without the bench states, in protocol version 1
//! and the current one (version 1 alone with the value tables), one line per session: `loop <version> <with
//! states> <ticks> <stack bytes> <replies> <digest> <accepted> <refused>`.

use core::hint::black_box;

use cortex_m_semihosting::hprintln;
use twocars::serial::Line;
use twocars::value_tables::ValueTables;

use super::probe;
use crate::main_loop::{script_as, Outcome, SCRIPT_CAPACITY};

/// Serves the session with `serve` (the unit's backend, its `tables`), with the bench states and
/// without, printing one `loop` line each, and exits.
pub fn run(
    tables: &'static [ValueTables<'static>],
    serve: impl Fn(&mut Line, &[u8], &'static [ValueTables<'static>]) -> Outcome,
) -> ! {
    probe::start();
    let mut bytes = [0u8; SCRIPT_CAPACITY];
    // The queues are a static on a board, outside the loop's stack.
    let Some(line) = cortex_m::singleton!(: Line = Line::new()) else {
        probe::fail();
    };
    // Protocol version 1 with the states and without, then the current version (not with the
    // tables).
    let current = twocars::protocol::frame::VERSION;
    let sessions = [(1, true), (1, false), (current, true), (current, false)];
    let count = if tables.is_empty() { 4 } else { 2 };
    for (version, with_states) in sessions.into_iter().take(count) {
        let Some(script) = script_as(version, with_states, !tables.is_empty(), &mut bytes)
            .and_then(|n| bytes.get(..n))
        else {
            hprintln!("script does not fit");
            continue;
        };
        let bottom = probe::paint();
        let start = probe::now();
        let session = serve(line, black_box(script), tables);
        let ticks = probe::ticks_since(start);
        let stack = probe::used(bottom);
        if !session.shutdown {
            hprintln!("session ended without Shutdown");
            continue;
        }
        hprintln!(
            "loop {} {} {} {} {} {:08x} {} {}",
            version,
            u8::from(with_states),
            ticks,
            stack,
            session.replies,
            session.digest,
            session.accepted,
            session.refused
        );
    }
    probe::succeed()
}
