//! The guidance loop every board runs: bytes from the serial port into the [`Unit`], replies
//! back, the watchdog polled between bytes. Generic over `embedded-io` 0.6 (the version the
//! STM32 HAL implements) and a millisecond clock; no allocation.

use embedded_io::{Read, ReadReady, Write};

use crate::unit::Unit;

/// A monotonic millisecond clock (wrapping), and the board's way to sleep until something
/// happens.
pub trait Clock {
    /// Milliseconds since start, wrapping at 2^32.
    fn now_ms(&self) -> u32;
    /// Sleeps until an interrupt: a received byte or the next clock tick. The default returns at
    /// once (busy polling).
    fn wait_for_event(&self) {}
}

/// Why the loop returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop<E> {
    /// The host sent Shutdown (and its acknowledgement was written).
    Shutdown,
    /// The serial port failed.
    Serial(E),
}

/// Writes every byte, retrying while the port takes none. Unlike `embedded_io::Write::write_all`
/// it has no panic path: a HAL that reports a full transmitter as `Ok(0)` (stm32f4xx-hal does)
/// makes `write_all` panic; here it only waits.
fn send<P: Write>(port: &mut P, mut bytes: &[u8]) -> Result<(), P::Error> {
    while !bytes.is_empty() {
        let n = port.write(bytes)?;
        bytes = bytes.get(n..).unwrap_or(&[]);
    }
    port.flush()
}

/// Serves the serial port until Shutdown or a port error.
pub fn serve<P, C>(port: &mut P, clock: &C, unit: &mut Unit) -> Stop<P::Error>
where
    P: Read + Write + ReadReady,
    C: Clock,
{
    let mut buf = [0u8; 32];
    loop {
        let now = clock.now_ms();
        if let Some(reply) = unit.poll(now) {
            crate::log_warn!("no valid State within the watchdog time: safe command");
            if let Err(e) = send(port, reply.as_bytes()) {
                return Stop::Serial(e);
            }
        }
        match port.read_ready() {
            Ok(false) => {
                clock.wait_for_event();
                continue;
            }
            Ok(true) => {}
            Err(e) => return Stop::Serial(e),
        }
        let n = match port.read(&mut buf) {
            Ok(n) => n,
            Err(e) => return Stop::Serial(e),
        };
        let mut bytes = buf.get(..n).unwrap_or(&[]);
        while !bytes.is_empty() {
            let (taken, reply) = unit.receive_slice(bytes, now);
            if let Some(reply) = reply {
                if let Err(e) = send(port, reply.as_bytes()) {
                    return Stop::Serial(e);
                }
                if reply.is_shutdown() {
                    return Stop::Shutdown;
                }
            }
            bytes = bytes.get(taken..).unwrap_or(&[]);
        }
    }
}
