//! The guidance unit over any serial port a HAL gives: our frames in, Commands out, through
//! embedded-hal-nb's non-blocking `serial::Read` and `serial::Write` (the embedded-hal 1.0
//! family's byte traits, which stm32f4xx-hal, rp2040-hal, nrf-hal and most HALs implement), with
//! the clock passed in by the caller. A polled loop for firmware that owns its UART through a
//! HAL; the interrupt-driven shells of [`crate::serial`] stay the flight path, where no byte
//! waits on the loop.
//!
//! ```
//! use embedded_hal_nb::nb;
//! use embedded_hal_nb::serial::{ErrorKind, ErrorType, Read, Write};
//! use twocars::polled::serve_pass;
//! use twocars::protocol::endpoint::Endpoint;
//!
//! /// A port with nothing to read that takes every byte (a HAL's `Serial` in firmware).
//! struct Quiet;
//! impl ErrorType for Quiet {
//!     type Error = ErrorKind;
//! }
//! impl Read<u8> for Quiet {
//!     fn read(&mut self) -> nb::Result<u8, ErrorKind> {
//!         Err(nb::Error::WouldBlock)
//!     }
//! }
//! impl Write<u8> for Quiet {
//!     fn write(&mut self, _: u8) -> nb::Result<(), ErrorKind> {
//!         Ok(())
//!     }
//!     fn flush(&mut self) -> nb::Result<(), ErrorKind> {
//!         Ok(())
//!     }
//! }
//!
//! let mut unit = Endpoint::<f32>::new();
//! // Each pass of the firmware's loop, with its millisecond clock.
//! let pass = serve_pass(&mut Quiet, &mut unit, 0).expect("the port does not fail");
//! assert_eq!((pass.bytes, pass.replies, pass.shutdown), (0, 0, false));
//! ```

use embedded_hal_nb::nb;
use embedded_hal_nb::serial::{Read, Write};

use crate::num::Scalar;
use crate::protocol::endpoint::Endpoint;

/// Most bytes one pass reads, so that a port that never runs dry still lets the loop run.
pub const MAX_PASS_BYTES: usize = 256;

/// What one pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PolledPass {
    /// Bytes read.
    pub bytes: usize,
    /// Replies written (the watchdog's safe command among them).
    pub replies: usize,
    /// A Shutdown was acknowledged: the caller stops serving.
    pub shutdown: bool,
}

/// One pass: the watchdog at `now_ms`, then the bytes the port has (at most
/// [`MAX_PASS_BYTES`]), each reply written whole before the next byte is read.
///
/// # Errors
/// The port's, from a read (other than `WouldBlock`) or a write; the unit keeps its state, and
/// the caller decides (a line fault is usually counted and the loop goes on).
pub fn serve_pass<P, S>(
    port: &mut P,
    unit: &mut Endpoint<S>,
    now_ms: u32,
) -> Result<PolledPass, P::Error>
where
    P: Read<u8> + Write<u8>,
    S: Scalar,
{
    let mut pass = PolledPass::default();
    if let Some(reply) = unit.poll(now_ms) {
        write_all(port, reply.as_bytes())?;
        pass.replies += 1;
    }
    while pass.bytes < MAX_PASS_BYTES {
        let byte = match port.read() {
            Ok(byte) => byte,
            Err(nb::Error::WouldBlock) => break,
            Err(nb::Error::Other(e)) => return Err(e),
        };
        pass.bytes += 1;
        if let Some(reply) = unit.receive(byte, now_ms) {
            let shutdown = reply.is_shutdown();
            write_all(port, reply.as_bytes())?;
            pass.replies += 1;
            if shutdown {
                pass.shutdown = true;
                break;
            }
        }
    }
    Ok(pass)
}

/// Serves the port until a Shutdown is acknowledged, reading the clock (ms) each pass.
///
/// # Errors
/// The port's first error; the caller may serve again with the same unit.
pub fn serve<P, S>(
    port: &mut P,
    unit: &mut Endpoint<S>,
    mut now_ms: impl FnMut() -> u32,
) -> Result<(), P::Error>
where
    P: Read<u8> + Write<u8>,
    S: Scalar,
{
    while !serve_pass(port, unit, now_ms())?.shutdown {}
    Ok(())
}

/// Writes `bytes` and flushes, waiting on the port as it asks.
fn write_all<P: Write<u8>>(port: &mut P, bytes: &[u8]) -> Result<(), P::Error> {
    for &byte in bytes {
        nb::block!(port.write(byte))?;
    }
    nb::block!(port.flush())
}
