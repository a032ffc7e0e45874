//! A captured MAVLink byte stream replayed through the firmware's serial path (the `replay`
//! image, and the host): what an autopilot sent the unit, in records of `[u32 ms][u16 length]
//! [bytes]` (little-endian; the milliseconds on the capturing host's clock), each fed at its
//! time. `cargo xtask run --autopilot ardupilot` writes one of ArduPilot Rover SITL's telemetry
//! with a chase; the image carries the capture named by `TWOCARS_MAVLINK_CAPTURE` at build time.

use core::cell::Cell;

use twocars::mavlink::Endpoint;
use twocars::serial::{Board, Line};

use crate::main_loop::ScriptedUart;
use crate::mavlink::serve_bytes;

/// The capture the image was built with (empty without `TWOCARS_MAVLINK_CAPTURE`).
pub static CAPTURE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/capture.bin"));

/// One record: the capturing clock's milliseconds and the bytes that arrived then.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Record<'a> {
    /// The capturing host's clock, ms.
    pub ms: u32,
    /// The bytes.
    pub bytes: &'a [u8],
}

/// The records of `capture`, up to the first that is cut short.
pub fn records(mut capture: &[u8]) -> impl Iterator<Item = Record<'_>> {
    core::iter::from_fn(move || {
        let (head, rest) = capture.split_first_chunk::<6>()?;
        let ms = u32::from_le_bytes([head[0], head[1], head[2], head[3]]);
        let length = usize::from(u16::from_le_bytes([head[4], head[5]]));
        let bytes = rest.get(..length)?;
        capture = rest.get(length..)?;
        Some(Record { ms, bytes })
    })
}

/// Appends a record to `out` (what the host writes).
#[cfg(not(target_os = "none"))]
pub fn push_record(out: &mut std::vec::Vec<u8>, ms: u32, bytes: &[u8]) {
    for chunk in bytes.chunks(usize::from(u16::MAX)) {
        out.extend_from_slice(&ms.to_le_bytes());
        out.extend_from_slice(&(chunk.len() as u16).to_le_bytes());
        out.extend_from_slice(chunk);
    }
}

/// A board whose clock is the record's.
struct ReplayBoard {
    now: Cell<u32>,
}

impl Board for ReplayBoard {
    fn now_ms(&self) -> u32 {
        self.now.get()
    }
    fn start_transmit(&self) {}
}

/// What a replay did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Replayed {
    /// Frames the endpoint sent.
    pub frames: u32,
    /// Digest of the bytes it sent (`ScriptedUart`'s).
    pub digest: u32,
    /// Setpoints among them.
    pub setpoints: u32,
    /// The stopwatch's ticks summed over the records (24-bit per record).
    pub ticks: u64,
    /// The capture's span, ms.
    pub span_ms: u32,
}

/// `capture` through the serial path with a fresh endpoint, each record at its time, timed
/// record by record with `stopwatch` (a down-counting 24-bit tick count; the host passes a
/// constant). Out of line, so that the bench's stack paint sees the endpoint.
#[inline(never)]
pub fn serve_replay(line: &mut Line, capture: &[u8], stopwatch: &dyn Fn() -> u32) -> Replayed {
    let (mut interrupt, mut main) = line.split();
    let mut endpoint = Endpoint::new();
    let board = ReplayBoard { now: Cell::new(0) };
    let (mut digest, mut ticks) = (0u32, 0u64);
    let (mut first, mut last) = (None, 0);
    for record in records(capture) {
        first.get_or_insert(record.ms);
        last = record.ms;
        board.now.set(record.ms);
        let start = stopwatch();
        let mut uart = ScriptedUart::new(record.bytes);
        uart.digest = digest;
        serve_bytes(&mut interrupt, &mut main, &mut uart, &board, &mut endpoint);
        digest = uart.digest;
        ticks += u64::from(start.wrapping_sub(stopwatch()) & 0x00FF_FFFF);
    }
    Replayed {
        frames: endpoint.frames_sent(),
        digest,
        setpoints: endpoint.counters().setpoints,
        ticks,
        span_ms: first.map_or(0, |f| last.wrapping_sub(f)),
    }
}
