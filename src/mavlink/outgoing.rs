//! MAVLink 2 frames the endpoint sends: the payload serialised by the `mavlink` crate's message
//! type (`MessageData::ser`, trailing zero bytes dropped as MAVLink 2 allows), the header and
//! the checksum written here (the crate's whole-frame writer keeps a panic path; docs/mavlink.md).

use ::mavlink::dialects::common::{
    MavAutopilot, MavModeFlag, MavParamType, MavSeverity, MavState, MavType, HEARTBEAT_DATA,
    NAMED_VALUE_FLOAT_DATA, PARAM_VALUE_DATA, STATUSTEXT_DATA,
};
use ::mavlink::{MavlinkVersion, MessageData};

use super::frame::STX_V2;
use super::params::{Params, SPECS};
use super::signing::{Signer, SIGNATURE_LEN};

/// Our component id: MAV_COMP_ID_ONBOARD_COMPUTER.
pub const COMPONENT: u8 = 191;
/// The MAVLink 2 header: start byte, length, two flag bytes, sequence, system, component and a
/// three-byte message id.
const HEADER: usize = 10;
/// The longest payload.
const MAX_PAYLOAD: usize = 255;
/// The longest MAVLink 2 frame, signed.
pub const MAX_OUT: usize = HEADER + MAX_PAYLOAD + 2 + SIGNATURE_LEN;
/// The longest PARAM_VALUE frame, signed: its payload is 25 bytes.
pub const MAX_PARAM_VALUE: usize = HEADER + 25 + 2 + SIGNATURE_LEN;

/// Our sequence number, and our signer where signing is on; frames go to a `send` closure
/// (the UART's transmit queue).
#[derive(Clone, Debug)]
pub struct Outbox {
    sequence: u8,
    /// Frames written.
    pub frames: u32,
    /// Signs every frame where set, at [`Outbox::timestamp`].
    pub signer: Option<Signer>,
    /// The signing clock now: 10 us since 2015-01-01 (the endpoint keeps it).
    pub timestamp: u64,
    /// Where the short messages of every period (SET_ATTITUDE_TARGET, NAMED_VALUE_FLOAT) are
    /// written: kept, as a buffer on the stack is cleared first (a [`MAX_OUT`] one costs
    /// about 130 instructions on the M4F). Every byte sent is written anew.
    short: [u8; SHORT_OUT],
}

impl Default for Outbox {
    fn default() -> Self {
        Outbox {
            sequence: 0,
            frames: 0,
            signer: None,
            timestamp: 0,
            short: [0; SHORT_OUT],
        }
    }
}

/// The frame buffer of a short message, signed.
const SHORT_OUT: usize = 64;

impl Outbox {
    /// A frame of `message` from (`system`, [`COMPONENT`]) handed to `send`.
    pub fn send<M: MessageData>(&mut self, system: u8, message: &M, send: &mut dyn FnMut(&[u8])) {
        self.send_as((system, COMPONENT), message, send);
    }

    /// A frame of `message` from (`system`, `component`) handed to `send` (a peer's frame, for
    /// the bench's script).
    pub fn send_as<M: MessageData>(
        &mut self,
        from: (u8, u8),
        message: &M,
        send: &mut dyn FnMut(&[u8]),
    ) {
        let header = Header {
            flags: u8::from(self.signer.is_some()),
            sequence: self.sequence,
            from,
        };
        let signer = self.signer.as_mut().map(|s| (s, self.timestamp));
        // A constant per message type: each instance keeps one of the two.
        if HEADER + M::ENCODED_LEN + 2 + SIGNATURE_LEN <= SHORT_OUT {
            let total = write_frame(&mut self.short, header, message, signer);
            send(self.short.get(..total).unwrap_or(&[]));
        } else {
            let mut frame = [0; MAX_OUT];
            let total = write_frame(&mut frame, header, message, signer);
            send(frame.get(..total).unwrap_or(&[]));
        }
        self.sequence = self.sequence.wrapping_add(1);
        self.frames = self.frames.wrapping_add(1);
    }

    /// Our HEARTBEAT: an onboard controller, no autopilot.
    pub fn heartbeat(&mut self, system: u8, send: &mut dyn FnMut(&[u8])) {
        let heartbeat = HEARTBEAT_DATA {
            custom_mode: 0,
            mavtype: MavType::MAV_TYPE_ONBOARD_CONTROLLER,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        };
        self.send(system, &heartbeat, send);
    }

    /// A STATUSTEXT of `severity` (at most 50 characters; longer text is cut).
    pub fn status_text(
        &mut self,
        system: u8,
        severity: MavSeverity,
        text: &str,
        send: &mut dyn FnMut(&[u8]),
    ) {
        let message = STATUSTEXT_DATA {
            severity,
            text: text.into(),
        };
        self.send(system, &message, send);
    }

    /// PARAM_VALUE of the parameter at `index`.
    pub fn param_value(
        &mut self,
        system: u8,
        params: &Params,
        index: usize,
        send: &mut dyn FnMut(&[u8]),
    ) {
        let (Some(spec), Some(value)) = (SPECS.get(index), params.get(index)) else {
            return;
        };
        let message = PARAM_VALUE_DATA {
            param_value: value,
            param_count: SPECS.len() as u16,
            param_index: index as u16,
            param_id: spec.name.into(),
            param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
        };
        self.send(system, &message, send);
    }

    /// NAMED_VALUE_FLOAT `name` = `value`, stamped `time_boot_ms` (our clock).
    pub fn named_value(
        &mut self,
        system: u8,
        time_boot_ms: u32,
        name: &str,
        value: f32,
        send: &mut dyn FnMut(&[u8]),
    ) {
        let message = NAMED_VALUE_FLOAT_DATA {
            time_boot_ms,
            value,
            name: name.into(),
        };
        self.send(system, &message, send);
    }

    /// NAMED_VALUE_INT `name` = `value`, stamped `time_boot_ms` (our clock).
    #[cfg(feature = "mavlink-team")]
    pub fn named_int(
        &mut self,
        system: u8,
        time_boot_ms: u32,
        name: &str,
        value: i32,
        send: &mut dyn FnMut(&[u8]),
    ) {
        let message = ::mavlink::dialects::common::NAMED_VALUE_INT_DATA {
            time_boot_ms,
            value,
            name: name.into(),
        };
        self.send(system, &message, send);
    }
}

/// A frame's header fields but its length and message id.
#[derive(Clone, Copy)]
struct Header {
    flags: u8,
    sequence: u8,
    /// System and component.
    from: (u8, u8),
}

/// Writes `message`'s frame into `frame` (room for it signed), signed by `signer` at its
/// timestamp where given: the frame's length.
fn write_frame<M: MessageData>(
    frame: &mut [u8],
    header: Header,
    message: &M,
    signer: Option<(&mut Signer, u64)>,
) -> usize {
    let Some((head, rest)) = frame.split_at_mut_checked(HEADER) else {
        return 0;
    };
    let room = rest
        .len()
        .saturating_sub(2 + SIGNATURE_LEN)
        .min(MAX_PAYLOAD);
    let Some(payload) = rest.get_mut(..room) else {
        return 0;
    };
    let length = message.ser(MavlinkVersion::V2, payload).min(room);
    let id = M::ID.to_le_bytes();
    let (system, component) = header.from;
    head.copy_from_slice(&[
        STX_V2,
        length as u8,
        header.flags,
        0,
        header.sequence,
        system,
        component,
        id[0],
        id[1],
        id[2],
    ]);
    let end = HEADER + length;
    let crc = ::mavlink::calculate_crc(frame.get(1..end).unwrap_or(&[]), M::EXTRA_CRC);
    if let Some(slot) = frame.get_mut(end..end + 2) {
        slot.copy_from_slice(&crc.to_le_bytes());
    }
    let mut total = end + 2;
    if let Some((signer, timestamp)) = signer {
        let block = signer.sign(frame.get(..total).unwrap_or(&[]), timestamp);
        if let Some(slot) = frame.get_mut(total..total + SIGNATURE_LEN) {
            slot.copy_from_slice(&block);
            total += SIGNATURE_LEN;
        }
    }
    total
}
