//! The main loop's bench session: the firmware's serial loop ([`crate::firmware::serve`]) fed a
//! fixed byte script from memory instead of a UART, so that `cargo xtask bench` can count its
//! instructions per State frame and paint its stack in QEMU, and the host can run the same
//! session and compare the replies.
//!
//! The script configures the paper's limits at [`DT`] for both roles, sends the bench [`STATES`]
//! under the paper policy, configures again under the near-field policy and sends them again,
//! then four inputs the unit refuses (an unknown type, a short State, a State with a NaN heading,
//! a bad CRC), ReadCounters and Shutdown. Without the states it is
//! the same session less its State frames: the difference of the two is the State frames' cost.

use crate::firmware::{serve, Clock, Stop};
use crate::message::{kind, Configure, StateMsg, ROLE_EVADER, ROLE_PURSUER};
use crate::unit::Unit;
use crate::wire::{cobs_encode, encode_frame, Deframer, Feed, Writer, CRC_LEN, MAX_FRAME};

use super::{DT, LIMITS, STATES};

/// Bytes the longest script takes, with room to spare.
pub const SCRIPT_CAPACITY: usize = 2048;

/// State frames in the script with the states: the bench states under each policy.
pub const STATE_FRAMES: usize = 2 * STATES.len();

/// A script being written: its frames COBS-encoded one after another into `out`.
struct Script<'a> {
    out: &'a mut [u8],
    len: usize,
    sequence: u16,
}

impl Script<'_> {
    /// Appends the frame of `message_type` with the next sequence number and `payload`.
    fn frame(
        &mut self,
        message_type: u8,
        payload: impl FnOnce(&mut Writer<'_>) -> Option<()>,
    ) -> Option<()> {
        self.sequence = self.sequence.wrapping_add(1);
        self.encode(message_type, self.sequence, payload)
    }

    fn encode(
        &mut self,
        message_type: u8,
        sequence: u16,
        payload: impl FnOnce(&mut Writer<'_>) -> Option<()>,
    ) -> Option<()> {
        let rest = self.out.get_mut(self.len..)?;
        self.len += encode_frame(message_type, sequence, payload, rest)?;
        Some(())
    }

    /// Appends the frame of `message_type`, sequence 0xBAD (outside the count) and `payload`
    /// with one bit of its CRC flipped: the frame encoded as the unit would get it, decoded, its
    /// CRC's low bit flipped, re-encoded.
    fn frame_with_bad_crc(
        &mut self,
        message_type: u8,
        payload: impl FnOnce(&mut Writer<'_>) -> Option<()>,
    ) -> Option<()> {
        let start = self.len;
        self.encode(message_type, 0xBAD, payload)?;
        let mut deframer = Deframer::<MAX_FRAME>::new();
        let (_, Feed::Frame(decoded)) = deframer.push_slice(self.out.get(start..self.len)?) else {
            return None;
        };
        let mut plain = [0u8; MAX_FRAME];
        let plain = plain.get_mut(..decoded.len())?;
        plain.copy_from_slice(decoded);
        *plain.get_mut(decoded.len().checked_sub(CRC_LEN)?)? ^= 1;
        self.len = start + cobs_encode(plain, self.out.get_mut(start..)?)?;
        Some(())
    }
}

/// The session's script written into `out`, with or without the bench states; its length, or
/// `None` if `out` is shorter than [`SCRIPT_CAPACITY`] needs.
pub fn script(with_states: bool, out: &mut [u8]) -> Option<usize> {
    let mut script = Script {
        out,
        len: 0,
        sequence: 0,
    };
    for policy in [0, 1] {
        let configure = Configure {
            limits: LIMITS,
            dt: DT,
            watchdog: 1.0,
            roles: ROLE_PURSUER | ROLE_EVADER,
            variant: 0,
            policy,
        };
        script.frame(kind::CONFIGURE, |w| configure.emit(w))?;
        if with_states {
            for (i, &(pursuer, evader)) in STATES.iter().enumerate() {
                let state = StateMsg {
                    time_ms: 10 * i as u32,
                    pursuer,
                    evader,
                };
                script.frame(kind::STATE, |w| state.emit(w))?;
            }
        }
    }
    let state = StateMsg {
        time_ms: 1_000,
        pursuer: [0.0; 3],
        evader: [5.0, 5.0, 0.0],
    };
    script.frame(0x7E, |_| Some(()))?;
    script.frame(kind::STATE, |w| w.u32(state.time_ms))?;
    let lost = StateMsg {
        evader: [5.0, 5.0, f32::NAN],
        ..state
    };
    script.frame(kind::STATE, |w| lost.emit(w))?;
    script.frame_with_bad_crc(kind::STATE, |w| state.emit(w))?;
    script.frame(kind::READ_COUNTERS, |_| Some(()))?;
    script.frame(kind::SHUTDOWN, |_| Some(()))?;
    Some(script.len)
}

/// The script ran out before a Shutdown: the loop's only way to end without one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScriptEnded;

impl embedded_io::Error for ScriptEnded {
    fn kind(&self) -> embedded_io::ErrorKind {
        embedded_io::ErrorKind::Other
    }
}

/// A serial port that reads a script and keeps a digest of what is written to it: the number of
/// replies (frame delimiters) and a rotate-and-xor hash of their bytes (a few instructions a
/// byte, as a UART's status poll and data write cost; enough to tell two reply streams apart).
#[derive(Debug)]
pub struct ScriptedPort<'a> {
    script: &'a [u8],
    /// Reply frames written.
    pub replies: u32,
    /// Hash of every byte written: `digest.rotate_left(5) ^ byte`, from 0.
    pub digest: u32,
}

impl<'a> ScriptedPort<'a> {
    /// A port that delivers `script`, then reports [`ScriptEnded`].
    pub fn new(script: &'a [u8]) -> Self {
        ScriptedPort {
            script,
            replies: 0,
            digest: 0,
        }
    }
}

impl embedded_io::ErrorType for ScriptedPort<'_> {
    type Error = ScriptEnded;
}

impl embedded_io::ReadReady for ScriptedPort<'_> {
    fn read_ready(&mut self) -> Result<bool, ScriptEnded> {
        if self.script.is_empty() {
            Err(ScriptEnded)
        } else {
            Ok(true)
        }
    }
}

impl embedded_io::Read for ScriptedPort<'_> {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, ScriptEnded> {
        let n = buf.len().min(self.script.len());
        let (now, rest) = self.script.split_at(n);
        if let Some(dst) = buf.get_mut(..n) {
            dst.copy_from_slice(now);
        }
        self.script = rest;
        Ok(n)
    }
}

impl embedded_io::Write for ScriptedPort<'_> {
    fn write(&mut self, buf: &[u8]) -> Result<usize, ScriptEnded> {
        for &byte in buf {
            self.digest = self.digest.rotate_left(5) ^ u32::from(byte);
            if byte == 0 {
                self.replies = self.replies.wrapping_add(1);
            }
        }
        Ok(buf.len())
    }
    fn flush(&mut self) -> Result<(), ScriptEnded> {
        Ok(())
    }
}

/// A clock that stands still: the watchdog never fires during a session.
#[derive(Clone, Copy, Debug, Default)]
pub struct StillClock;

impl Clock for StillClock {
    fn now_ms(&self) -> u32 {
        0
    }
}

/// What one session of the serial loop left: whether it ended at its Shutdown, the replies and
/// their digest ([`ScriptedPort`]), the unit's accepted and refused inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The loop returned at the script's Shutdown.
    pub shutdown: bool,
    /// Reply frames written.
    pub replies: u32,
    /// Digest of the replies' bytes.
    pub digest: u32,
    /// Inputs the unit accepted.
    pub accepted: u32,
    /// Inputs the unit refused, all kinds.
    pub refused: u32,
}

/// The firmware's loop over `script`, with a fresh unit and a still clock. The unit and the port
/// live in this frame, as in a firmware's `main`; out of line, so that the bench's stack paint
/// sees them.
#[inline(never)]
pub fn serve_script(script: &[u8]) -> Outcome {
    let mut port = ScriptedPort::new(script);
    let mut unit = Unit::new();
    let stop = serve(&mut port, &StillClock, &mut unit);
    let counters = unit.counters();
    Outcome {
        shutdown: stop == Stop::Shutdown,
        replies: port.replies,
        digest: port.digest,
        accepted: counters.accepted,
        refused: counters.errors.iter().fold(0, |a, &b| a.wrapping_add(b)),
    }
}
