//! Interrupt-driven serial I/O, the same on every board: the UART's interrupt moves bytes between
//! its data registers and two `heapless` single-producer, single-consumer queues; the guidance
//! loop drains the receive queue into the [`Endpoint`] and queues its replies, and never waits
//! on the line. Line faults (overrun, framing, noise, parity, a full queue) are counted, never fatal.
//!
//! A board supplies [`UartRegisters`] (its data and status registers, for the interrupt) and
//! [`Board`] (clock, sleep, and the transmitter's start, for the loop); the rest is here and runs
//! unchanged on the host against a UART model (`twocars_sim::uart_model`).

use core::sync::atomic::{AtomicU32, Ordering};

use heapless::spsc::{Consumer, Producer, Queue};

use crate::num::Scalar;
use crate::protocol::endpoint::Endpoint;
use crate::protocol::message::LineCounts;

/// Receive queue slots (it holds one byte fewer): 14 State frames, 5.5 ms of input at 921600
/// baud. A power of two, so the queue's index wrap is a mask.
pub const RX_CAPACITY: usize = 512;
/// Transmit queue slots (one byte fewer): five of the longest replies.
pub const TX_CAPACITY: usize = 512;

/// What the UART flagged with a received byte.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RxFlags {
    /// A byte was lost before this one (the data register was not read in time).
    pub overrun: bool,
    /// This byte had no stop bit: it is garbage.
    pub framing: bool,
    /// Noise was sampled in this byte: it is kept, its frame's CRC decides.
    pub noise: bool,
    /// This byte's parity failed: it is garbage.
    pub parity: bool,
}

/// A UART's registers as its interrupt handler sees them.
pub trait UartRegisters {
    /// The received byte, if the data register holds one, with the faults flagged for it (both
    /// cleared by this read). `Some((None, flags))` reports faults without a byte.
    fn take_received(&mut self) -> Option<(Option<u8>, RxFlags)>;
    /// Whether the transmit data register can take a byte.
    fn can_transmit(&self) -> bool;
    /// Writes `byte` to the transmit data register (only after [`Self::can_transmit`]).
    fn transmit(&mut self, byte: u8);
    /// Nothing left to send: stop the transmit-empty interrupt (on a UART whose interrupt is a
    /// level while the register is empty) or acknowledge it (on one that signals each byte sent).
    fn transmit_idle(&mut self);
}

/// The loop's view of its board.
pub trait Board {
    /// Milliseconds since start, wrapping at 2^32 (the watchdog's clock).
    fn now_ms(&self) -> u32;
    /// Starts the transmitter after replies were queued: enable or pend the UART's transmit
    /// interrupt, whose handler then drains the transmit queue.
    fn start_transmit(&self);
    /// Sleeps until an interrupt while `idle()` holds, checked with interrupts masked so that a
    /// byte arriving between the check and the sleep still wakes it. The default returns at once.
    fn sleep_while(&self, idle: &mut dyn FnMut() -> bool) {
        let _ = idle;
    }
    /// The board's status flags for Counters ([`crate::protocol::message::BOARD_FALLBACK_CLOCK`]).
    /// The default: none.
    fn status_flags(&self) -> u32 {
        0
    }
}

/// Line fault counts. Each is written by one side only (the interrupt, or the loop for
/// `tx_full`), so a load and a store count it: no read-modify-write atomics, which the
/// Cortex-M0 lacks.
#[derive(Debug, Default)]
pub struct LineFaults {
    overrun: AtomicU32,
    framing: AtomicU32,
    noise: AtomicU32,
    parity: AtomicU32,
    rx_full: AtomicU32,
    tx_full: AtomicU32,
}

fn bump(counter: &AtomicU32) {
    counter.store(
        counter.load(Ordering::Relaxed).saturating_add(1),
        Ordering::Relaxed,
    );
}

impl LineFaults {
    /// No faults.
    pub const fn new() -> Self {
        LineFaults {
            overrun: AtomicU32::new(0),
            framing: AtomicU32::new(0),
            noise: AtomicU32::new(0),
            parity: AtomicU32::new(0),
            rx_full: AtomicU32::new(0),
            tx_full: AtomicU32::new(0),
        }
    }

    /// The counts now.
    pub fn snapshot(&self) -> LineCounts {
        LineCounts {
            overrun: self.overrun.load(Ordering::Relaxed),
            framing: self.framing.load(Ordering::Relaxed),
            noise: self.noise.load(Ordering::Relaxed),
            parity: self.parity.load(Ordering::Relaxed),
            rx_full: self.rx_full.load(Ordering::Relaxed),
            tx_full: self.tx_full.load(Ordering::Relaxed),
        }
    }
}

/// The queues and fault counts a board's UART shares between its interrupt and the loop; a
/// board keeps one in a `static` and [`Line::split`]s it once.
#[derive(Debug)]
pub struct Line {
    rx: Queue<u8, RX_CAPACITY>,
    tx: Queue<u8, TX_CAPACITY>,
    faults: LineFaults,
}

impl Default for Line {
    fn default() -> Self {
        Self::new()
    }
}

impl Line {
    /// Empty queues, no faults.
    pub const fn new() -> Self {
        Line {
            rx: Queue::new(),
            tx: Queue::new(),
            faults: LineFaults::new(),
        }
    }

    /// The interrupt's end and the loop's end.
    pub fn split(&mut self) -> (InterruptEnd<'_>, LoopEnd<'_>) {
        let (rx_in, rx_out) = self.rx.split();
        let (tx_in, tx_out) = self.tx.split();
        let faults = &self.faults;
        (
            InterruptEnd {
                received: rx_in,
                to_send: tx_out,
                faults,
                dropped: false,
            },
            LoopEnd {
                received: rx_out,
                to_send: tx_in,
                faults,
                chunk: [0; CHUNK],
            },
        )
    }
}

/// The UART interrupt's end of a [`Line`].
pub struct InterruptEnd<'a> {
    received: Producer<'a, u8, RX_CAPACITY>,
    to_send: Consumer<'a, u8, TX_CAPACITY>,
    faults: &'a LineFaults,
    /// A received byte was dropped for a full queue: its frame is to be ended.
    dropped: bool,
}

impl InterruptEnd<'_> {
    /// The UART's interrupt handler: every received byte into the receive queue (its faults
    /// counted), then the transmitter fed from the transmit queue while it takes bytes.
    pub fn on_interrupt<U: UartRegisters>(&mut self, uart: &mut U) {
        while let Some((byte, flags)) = uart.take_received() {
            self.receive(byte, flags);
        }
        while uart.can_transmit() {
            match self.to_send.dequeue() {
                Some(byte) => uart.transmit(byte),
                None => {
                    uart.transmit_idle();
                    break;
                }
            }
        }
    }

    /// Queues a received byte. A fault ends the frame it lands in: a delimiter goes into the
    /// queue in place of a byte that failed its framing or parity (garbage), or before a byte
    /// that followed a lost one (overrun). The damaged frame is refused as usual; the next one
    /// arrives whole, even when the fault hit its delimiter.
    fn receive(&mut self, byte: Option<u8>, flags: RxFlags) {
        if flags != RxFlags::default() && self.fault(flags) {
            return;
        }
        if let Some(byte) = byte {
            self.push(byte);
        }
    }

    /// Counts `flags` and ends the frame; whether the byte that came with them is garbage.
    #[cold]
    #[inline(never)]
    fn fault(&mut self, flags: RxFlags) -> bool {
        let faults = self.faults;
        for (flagged, counter) in [
            (flags.overrun, &faults.overrun),
            (flags.framing, &faults.framing),
            (flags.noise, &faults.noise),
            (flags.parity, &faults.parity),
        ] {
            if flagged {
                bump(counter);
            }
        }
        let garbage = flags.framing || flags.parity;
        if flags.overrun || garbage {
            self.push(0);
        }
        garbage
    }

    /// Queues `byte`; a byte dropped for a full queue ends its frame the same way (a delimiter
    /// goes in first once there is room again).
    fn push(&mut self, byte: u8) {
        if self.dropped && byte != 0 && self.received.enqueue(0).is_err() {
            bump(&self.faults.rx_full);
            return;
        }
        self.dropped = self.received.enqueue(byte).is_err();
        if self.dropped {
            bump(&self.faults.rx_full);
        }
    }
}

/// The loop's end of a [`Line`].
pub struct LoopEnd<'a> {
    received: Consumer<'a, u8, RX_CAPACITY>,
    to_send: Producer<'a, u8, TX_CAPACITY>,
    faults: &'a LineFaults,
    /// Bytes taken from the receive queue, fed to the unit as a slice (kept here: a local
    /// array would be zeroed on every pass).
    chunk: [u8; CHUNK],
}

/// What one [`service`] pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pass {
    /// Bytes taken from the receive queue.
    pub bytes: usize,
    /// Replies queued (or dropped for a full transmit queue).
    pub replies: usize,
    /// A Shutdown was acknowledged: the session is over.
    pub shutdown: bool,
}

impl LoopEnd<'_> {
    /// Whether the receive queue is empty.
    pub fn nothing_received(&self) -> bool {
        !self.received.ready()
    }

    /// Whether every queued reply byte went to the UART.
    #[allow(clippy::len_zero)] // heapless 0.8's Producer has no `is_empty`.
    pub fn all_sent(&self) -> bool {
        self.to_send.len() == 0
    }

    /// Free bytes in the transmit queue.
    pub fn room(&self) -> usize {
        self.to_send.capacity() - self.to_send.len()
    }

    /// The line's fault counts.
    pub fn faults(&self) -> LineCounts {
        self.faults.snapshot()
    }

    /// The next received byte, if any.
    pub fn take(&mut self) -> Option<u8> {
        self.received.dequeue()
    }

    /// Queues a whole frame for the transmitter, or drops it whole (counted) if the queue has
    /// no room for it. The caller starts the transmitter ([`Board::start_transmit`]).
    pub fn queue(&mut self, bytes: &[u8]) {
        queue(&mut self.to_send, self.faults, bytes);
    }
}

/// Bytes taken from the receive queue at a time.
const CHUNK: usize = 32;

/// Queues a whole reply, or drops it whole (counted) if the queue has no room for it: a
/// receiver resynchronises on the next delimiter either way, but half a frame would cost it the
/// next one too.
fn queue(to_send: &mut Producer<'_, u8, TX_CAPACITY>, faults: &LineFaults, bytes: &[u8]) {
    let room = to_send.capacity() - to_send.len();
    if bytes.len() > room {
        bump(&faults.tx_full);
        return;
    }
    for &byte in bytes {
        // Cannot fail: there was room for all of them, and only this end adds.
        let _ = to_send.enqueue(byte);
    }
}

/// One pass of the loop: the watchdog, then every byte received so far, replies queued and the
/// transmitter started.
pub fn service<B: Board, S: Scalar>(
    line: &mut LoopEnd<'_>,
    board: &B,
    unit: &mut Endpoint<S>,
) -> Pass {
    let mut pass = Pass::default();
    let now = board.now_ms();
    if let Some(reply) = unit.poll(now) {
        crate::log::log_warn!("no valid State within the watchdog time: safe command");
        queue(&mut line.to_send, line.faults, reply.as_bytes());
        pass.replies += 1;
    }
    unit.record_line(line.faults());
    unit.set_board_status(board.status_flags());
    loop {
        let LoopEnd {
            received,
            to_send,
            faults,
            chunk,
        } = line;
        let mut n = 0;
        for slot in chunk.iter_mut() {
            match received.dequeue() {
                Some(byte) => *slot = byte,
                None => break,
            }
            n += 1;
        }
        if n == 0 {
            break;
        }
        pass.bytes += n;
        let mut bytes = chunk.get(..n).unwrap_or(&[]);
        while !bytes.is_empty() {
            let (taken, reply) = unit.receive_slice(bytes, now);
            if let Some(reply) = reply {
                queue(to_send, faults, reply.as_bytes());
                pass.replies += 1;
                if reply.is_shutdown() {
                    pass.shutdown = true;
                    board.start_transmit();
                    return pass;
                }
            }
            bytes = bytes.get(taken..).unwrap_or(&[]);
        }
    }
    if pass.replies > 0 {
        board.start_transmit();
    }
    pass
}

/// Serves the line until Shutdown (acknowledged and queued; the caller waits for
/// [`LoopEnd::all_sent`] before it stops the board). Sleeps while nothing was received.
pub fn serve<B: Board, S: Scalar>(line: &mut LoopEnd<'_>, board: &B, unit: &mut Endpoint<S>) {
    loop {
        if service(line, board, unit).shutdown {
            return;
        }
        board.sleep_while(&mut || line.nothing_received());
    }
}

/// [`serve`], then waits (asleep) until the ShutdownAck has left the transmit queue: a board's
/// `main` can stop once this returns. Inlined into the board's `main`: out of line, the law and
/// the encoder are not inlined into it and the QEMU image grows by 152 B.
#[inline(always)]
pub fn serve_to_shutdown<B: Board, S: Scalar>(
    line: &mut LoopEnd<'_>,
    board: &B,
    unit: &mut Endpoint<S>,
) {
    serve(line, board, unit);
    while !line.all_sent() {
        board.sleep_while(&mut || !line.all_sent());
    }
}
