//! The host's end of the serial link: builds frames for the unit and decodes its replies, with
//! the same wire code the firmware uses.

use twocars::protocol::frame::{
    encode_frame_as, Deframer, Feed, Frame, WireError, MAX_ENCODED, MAX_FRAME, VERSION, VERSION_1,
    VERSION_2,
};
use twocars::protocol::message::{
    kind, CommandMsg, Configure, Counters, ErrorMsg, StateMsg, TeammateMsg,
};

/// A decoded reply of the unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reply {
    /// Configure accepted (echoed sequence) and the policy byte in effect (`None` from a unit
    /// that predates it).
    ConfigureAck(u16, Option<u8>),
    /// A command (echoed sequence; 0 for the watchdog's).
    Command(u16, CommandMsg),
    /// Counters (echoed sequence).
    Counters(u16, Counters),
    /// An input refused (sequence, if known).
    Error(Option<u16>, ErrorMsg),
    /// Shutdown accepted (echoed sequence).
    ShutdownAck(u16),
    /// Reset accepted (echoed sequence).
    ResetAck(u16),
    /// Teammate accepted (echoed sequence).
    TeammateAck(u16),
}

fn frame(
    message_type: u8,
    sequence: u16,
    emit: impl FnOnce(&mut twocars::protocol::frame::Writer<'_>) -> Option<()>,
) -> Vec<u8> {
    frame_as(VERSION, message_type, sequence, emit)
}

fn frame_as(
    version: u8,
    message_type: u8,
    sequence: u16,
    emit: impl FnOnce(&mut twocars::protocol::frame::Writer<'_>) -> Option<()>,
) -> Vec<u8> {
    let mut out = [0u8; MAX_ENCODED];
    let n = encode_frame_as(version, message_type, sequence, emit, &mut out)
        .expect("message fits a frame");
    out[..n].to_vec()
}

/// A Configure frame.
pub fn configure(sequence: u16, m: &Configure) -> Vec<u8> {
    frame(kind::CONFIGURE, sequence, |w| m.emit(w))
}

/// A State frame.
pub fn state(sequence: u16, m: &StateMsg) -> Vec<u8> {
    frame(kind::STATE, sequence, |w| m.emit(w))
}

/// A State frame of protocol version 1 (the evader's fix at the timestamp).
pub fn state_v1(sequence: u16, m: &StateMsg) -> Vec<u8> {
    frame_as(VERSION_1, kind::STATE, sequence, |w| m.emit_v1(w))
}

/// A State frame of protocol version 2 (a Command without the chaser in reply).
pub fn state_v2(sequence: u16, m: &StateMsg) -> Vec<u8> {
    frame_as(VERSION_2, kind::STATE, sequence, |w| m.emit(w))
}

/// A Configure frame of protocol version 2 (no team).
pub fn configure_v2(sequence: u16, m: &Configure) -> Vec<u8> {
    frame_as(VERSION_2, kind::CONFIGURE, sequence, |w| m.emit_v2(w))
}

/// A Teammate frame.
pub fn teammate(sequence: u16, m: &TeammateMsg) -> Vec<u8> {
    frame(kind::TEAMMATE, sequence, |w| m.emit(w))
}

/// A Configure frame of protocol version 1 (no field settings).
pub fn configure_v1(sequence: u16, m: &Configure) -> Vec<u8> {
    frame_as(VERSION_1, kind::CONFIGURE, sequence, |w| m.emit_v1(w))
}

/// A ReadCounters frame.
pub fn read_counters(sequence: u16) -> Vec<u8> {
    frame(kind::READ_COUNTERS, sequence, |_| Some(()))
}

/// A Reset frame.
pub fn reset(sequence: u16) -> Vec<u8> {
    frame(kind::RESET, sequence, |_| Some(()))
}

/// A Shutdown frame.
pub fn shutdown(sequence: u16) -> Vec<u8> {
    frame(kind::SHUTDOWN, sequence, |_| Some(()))
}

/// A frame of any type with any payload (for tests of refusals).
pub fn raw(message_type: u8, sequence: u16, payload: &[u8]) -> Vec<u8> {
    frame(message_type, sequence, |w| w.put(payload))
}

/// [`raw`] in protocol `version`.
pub fn raw_as(version: u8, message_type: u8, sequence: u16, payload: &[u8]) -> Vec<u8> {
    frame_as(version, message_type, sequence, |w| w.put(payload))
}

/// The frames (decoded) and refusals a deframer of `MAX_FRAME` bytes makes of `stream`: fed byte
/// by byte (`cut` = `None`, [`Deframer::push`]) or in slices of `cut` bytes, each slice fed until
/// the deframer has taken all of it ([`Deframer::push_slice`], the firmware's way).
pub fn deframe(stream: &[u8], cut: Option<usize>) -> Vec<Result<Vec<u8>, WireError>> {
    let owned = |feed: Feed<'_>| match feed {
        Feed::Pending => None,
        Feed::Frame(f) => Some(Ok(f.to_vec())),
        Feed::Error(e) => Some(Err(e)),
    };
    let mut deframer = Deframer::<MAX_FRAME>::new();
    let Some(cut) = cut else {
        return stream
            .iter()
            .filter_map(|&b| owned(deframer.push(b)))
            .collect();
    };
    let mut out = Vec::new();
    for chunk in stream.chunks(cut.max(1)) {
        let mut rest = chunk;
        while !rest.is_empty() {
            let (taken, feed) = deframer.push_slice(rest);
            assert!(
                (1..=rest.len()).contains(&taken),
                "took {taken} of {}",
                rest.len()
            );
            out.extend(owned(feed));
            rest = &rest[taken..];
        }
    }
    out
}

/// Decodes the unit's replies from a byte stream.
#[derive(Default)]
pub struct ReplyDecoder {
    deframer: Deframer<MAX_FRAME>,
}

impl ReplyDecoder {
    /// Feeds bytes; returns every complete reply (or why a frame was not one).
    pub fn feed(&mut self, bytes: &[u8]) -> Vec<Result<Reply, WireError>> {
        let mut out = Vec::new();
        for &b in bytes {
            match self.deframer.push(b) {
                Feed::Pending => {}
                Feed::Error(e) => out.push(Err(e)),
                Feed::Frame(f) => out.push(decode(f)),
            }
        }
        out
    }
}

fn decode(bytes: &[u8]) -> Result<Reply, WireError> {
    let f = Frame::new_checked(bytes)?;
    let seq = f.sequence();
    match f.message_type() {
        kind::CONFIGURE_ACK => Ok(Reply::ConfigureAck(seq, f.payload().first().copied())),
        kind::SHUTDOWN_ACK => Ok(Reply::ShutdownAck(seq)),
        kind::RESET_ACK => Ok(Reply::ResetAck(seq)),
        kind::TEAMMATE_ACK => Ok(Reply::TeammateAck(seq)),
        kind::COMMAND => Ok(Reply::Command(seq, CommandMsg::parse(f.payload())?)),
        kind::COUNTERS => Ok(Reply::Counters(seq, Counters::parse(f.payload())?)),
        kind::ERROR => {
            let e = ErrorMsg::parse(f.payload())?;
            Ok(Reply::Error((e.sequence_known == 1).then_some(seq), e))
        }
        _ => Err(WireError::UnknownType),
    }
}
