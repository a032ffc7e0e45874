//! The MAVLink images' loop: the UART's receive queue drained into the [`Endpoint`], its frames
//! queued for the transmitter, the heartbeat and staleness checked every pass. The same
//! interrupt-driven line ([`crate::serial`]) as the COBS images; the loop never waits on it.

use super::Endpoint;
use crate::serial::{Board, LoopEnd};

/// Serves the link for good. Sleeps while nothing was received (the board's millisecond tick
/// wakes it for the heartbeat). The board's status flags go to the endpoint first.
pub fn serve_mavlink<B: Board>(line: &mut LoopEnd<'_>, board: &B, endpoint: &mut Endpoint) -> ! {
    endpoint.set_board_status(board.status_flags());
    loop {
        service(line, board, endpoint);
        board.sleep_while(&mut || line.nothing_received());
    }
}

/// One pass: the heartbeat and staleness check, then every byte received so far; the
/// transmitter started if anything was queued. Returns the bytes taken.
pub fn service<B: Board>(line: &mut LoopEnd<'_>, board: &B, endpoint: &mut Endpoint) -> usize {
    let now = board.now_ms();
    let mut queued = false;
    let mut taken = 0;
    endpoint.poll_within(now, line.room(), &mut |frame| {
        queued = true;
        line.queue(frame);
    });
    while let Some(byte) = line.take() {
        taken += 1;
        endpoint.receive(byte, now, &mut |frame| {
            queued = true;
            line.queue(frame);
        });
    }
    if queued {
        board.start_transmit();
    }
    taken
}
