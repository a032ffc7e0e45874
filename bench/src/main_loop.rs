//! The main loop's bench session: the firmware's serial path — the UART interrupt's handler
//! ([`twocars::serial::InterruptEnd::on_interrupt`]) and the loop ([`service`]) over the `heapless` queues — fed a
//! fixed byte script from memory by a scripted UART, so that `cargo xtask bench` can count its
//! instructions per State frame and paint its stack in QEMU, and the host can run the same
//! session and compare the replies.
//!
//! The script configures the paper's limits at [`DT`] for both roles, sends the bench [`STATES`]
//! under the paper policy, configures again under the near-field policy and sends them again,
//! then four inputs the unit refuses (an unknown type, a short State, a State with a NaN heading,
//! a bad CRC), ReadCounters and Shutdown, in protocol version 1 (exact states: the estimator's
//! cost is a bench of its own). Without the states it is
//! the same session less its State frames: the difference of the two is the State frames' cost.
//! With the tables, one Configure selects the value tables (policy 2) and the states are the
//! points where the bench reads them ([`TABLE_POINTS`], the pursuer at the origin heading +x).

use twocars::num::Scalar;
use twocars::protocol::endpoint::Endpoint;
use twocars::protocol::frame::{
    cobs_encode, encode_frame_as, Deframer, Feed, Writer, CRC_LEN, MAX_FRAME, VERSION_1, VERSION_2,
};
use twocars::protocol::message::{
    kind, Configure, FieldConfig, StateMsg, TeamConfig, ROLE_EVADER, ROLE_PURSUER,
};
use twocars::serial::{service, Board, Line, RxFlags, UartRegisters};

use twocars::value_tables::ValueTables;

use crate::{DT, LIMITS, STATES, TABLE_POINTS};

/// Bytes the longest script takes, with room to spare.
pub const SCRIPT_CAPACITY: usize = 2048;

/// State frames in the script with the states: the bench states under each policy, or, with
/// the tables, the table points.
pub fn state_frames(tables: bool) -> usize {
    if tables {
        TABLE_POINTS.len()
    } else {
        2 * STATES.len()
    }
}

/// The script's (pursuer, evader) states, m and rad: the bench states, or with the tables
/// the table points (r_p) with the pursuer at the origin heading +x.
fn states(tables: bool) -> impl Iterator<Item = ([f32; 3], [f32; 3])> {
    let r_p = 1.0 / LIMITS[1];
    let near = TABLE_POINTS
        .iter()
        .map(move |&[x, y, phi]| ([0.0; 3], [x * r_p, y * r_p, phi]));
    let far = STATES.iter().copied();
    far.filter(move |_| !tables)
        .chain(near.filter(move |_| tables))
}

/// A script being written: its frames COBS-encoded one after another into `out`.
struct Script<'a> {
    out: &'a mut [u8],
    len: usize,
    sequence: u16,
    /// The protocol version of every frame.
    version: u8,
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
        self.len += encode_frame_as(self.version, message_type, sequence, payload, rest)?;
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

/// The session's script written into `out` in protocol version 1, with or without its states,
/// for a unit with or without the bench's value tables; its length, or `None` if `out` is
/// shorter than [`SCRIPT_CAPACITY`] needs.
pub fn script(with_states: bool, tables: bool, out: &mut [u8]) -> Option<usize> {
    script_as(VERSION_1, with_states, tables, out)
}

/// [`script`] in protocol `version` (1 or [`twocars::protocol::frame::VERSION`]): from version 2 the Configure carries
/// the field's settings (exact: the states go through the unit's estimator as they come) and
/// each State its evader fix's time; from version 3 the Configure says it has no team.
pub fn script_as(version: u8, with_states: bool, tables: bool, out: &mut [u8]) -> Option<usize> {
    let mut script = Script {
        out,
        len: 0,
        sequence: 0,
        version,
    };
    let v1 = version == VERSION_1;
    let policies: &[u8] = if tables { &[2] } else { &[0, 1] };
    for &policy in policies {
        let configure = Configure {
            limits: LIMITS,
            dt: DT,
            watchdog: 1.0,
            roles: ROLE_PURSUER | ROLE_EVADER,
            variant: 0,
            policy,
            field: FieldConfig::EXACT,
            team: TeamConfig::NONE,
        };
        script.frame(kind::CONFIGURE, |w| match version {
            VERSION_1 => configure.emit_v1(w),
            VERSION_2 => configure.emit_v2(w),
            _ => configure.emit(w),
        })?;
        if with_states {
            for (i, (pursuer, evader)) in states(tables).enumerate() {
                let state = StateMsg::exact(10 * i as u32, pursuer, evader);
                script.frame(kind::STATE, |w| emit_state(v1, &state, w))?;
            }
        }
    }
    let state = StateMsg::exact(1_000, [0.0; 3], [5.0, 5.0, 0.0]);
    script.frame(0x7E, |_| Some(()))?;
    script.frame(kind::STATE, |w| w.u32(state.time_ms))?;
    let lost = StateMsg {
        evader: [5.0, 5.0, f32::NAN],
        ..state
    };
    script.frame(kind::STATE, |w| emit_state(v1, &lost, w))?;
    script.frame_with_bad_crc(kind::STATE, |w| emit_state(v1, &state, w))?;
    script.frame(kind::READ_COUNTERS, |_| Some(()))?;
    script.frame(kind::SHUTDOWN, |_| Some(()))?;
    Some(script.len)
}

/// `state`'s payload in protocol version 1 (`v1`) or the current one.
fn emit_state(v1: bool, state: &StateMsg, w: &mut Writer<'_>) -> Option<()> {
    if v1 {
        state.emit_v1(w)
    } else {
        state.emit(w)
    }
}

/// A UART without FIFO whose receiver delivers a script and whose transmitter keeps a digest of
/// what is written: the number of replies (frame delimiters) and a rotate-and-xor hash of their
/// bytes (enough to tell two reply streams apart). One byte each way per interrupt, as such a
/// UART raises them.
#[derive(Debug)]
pub struct ScriptedUart<'a> {
    script: &'a [u8],
    /// A script byte is in the receive data register.
    received: Option<u8>,
    /// The transmit data register is empty.
    pub(crate) tx_empty: bool,
    /// Reply frames written.
    pub replies: u32,
    /// Hash of every byte written: `digest.rotate_left(5) ^ byte`, from 0.
    pub digest: u32,
}

impl<'a> ScriptedUart<'a> {
    /// A UART about to receive `script`.
    pub fn new(script: &'a [u8]) -> Self {
        ScriptedUart {
            script,
            received: None,
            tx_empty: false,
            replies: 0,
            digest: 0,
        }
    }

    /// The next script byte lands in the data register; false once the script is over.
    pub(crate) fn arrive(&mut self) -> Option<u8> {
        let (&byte, rest) = self.script.split_first()?;
        self.script = rest;
        self.received = Some(byte);
        Some(byte)
    }
}

impl UartRegisters for ScriptedUart<'_> {
    fn take_received(&mut self) -> Option<(Option<u8>, RxFlags)> {
        self.received.take().map(|b| (Some(b), RxFlags::default()))
    }
    fn can_transmit(&self) -> bool {
        self.tx_empty
    }
    fn transmit(&mut self, byte: u8) {
        self.tx_empty = false;
        self.digest = self.digest.rotate_left(5) ^ u32::from(byte);
        if byte == 0 {
            self.replies = self.replies.wrapping_add(1);
        }
    }
    fn transmit_idle(&mut self) {}
}

/// A board whose clock stands still (the watchdog never fires during a session) and whose
/// transmitter is drained by the session's driver.
#[derive(Clone, Copy, Debug, Default)]
pub struct StillBoard;

impl Board for StillBoard {
    fn now_ms(&self) -> u32 {
        0
    }
    fn start_transmit(&self) {}
}

/// What one session of the serial loop left: whether it ended at its Shutdown, the replies and
/// their digest ([`ScriptedUart`]), the unit's accepted and refused inputs.
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

/// The firmware's serial path over `script` with a fresh unit and a still clock: each script
/// byte raised as a receive interrupt (the shared handler queues it), the loop's pass after each
/// frame's delimiter, then one transmit interrupt per reply byte until the queue is empty. The
/// unit lives in this frame, as in a firmware's `main` (the queues in `line`, a static on a
/// board); out of line, so that the bench's stack paint sees it.
#[inline(never)]
pub fn serve_script(
    line: &mut Line,
    script: &[u8],
    tables: &'static [ValueTables<'static>],
) -> Outcome {
    serve_script_on::<f32>(line, script, tables)
}

/// [`serve_script`] with the fixed-point unit (the Cortex-M0 image).
#[inline(never)]
pub fn serve_script_fixed(line: &mut Line, script: &[u8]) -> Outcome {
    serve_script_on::<twocars::num::fixed::Fixed>(line, script, &[])
}

/// [`serve_script`] with the unit on backend `S`, with `tables`.
#[inline(always)]
pub fn serve_script_on<S: Scalar>(
    line: &mut Line,
    script: &[u8],
    tables: &'static [ValueTables<'static>],
) -> Outcome {
    let (mut interrupt, mut main) = line.split();
    let mut uart = ScriptedUart::new(script);
    let mut unit = Endpoint::<S>::new();
    unit.set_tables(tables);
    let mut shutdown = false;
    while !shutdown {
        let mut arrived = false;
        while let Some(byte) = uart.arrive() {
            arrived = true;
            interrupt.on_interrupt(&mut uart);
            if byte == 0 {
                break;
            }
        }
        shutdown = service(&mut main, &StillBoard, &mut unit).shutdown;
        loop {
            uart.tx_empty = true;
            interrupt.on_interrupt(&mut uart);
            if uart.tx_empty {
                break;
            }
        }
        if !arrived {
            break;
        }
    }
    let counters = unit.counters();
    Outcome {
        shutdown,
        replies: uart.replies,
        digest: uart.digest,
        accepted: counters.accepted,
        refused: counters.errors.iter().fold(0, |a, &b| a.wrapping_add(b)),
    }
}
