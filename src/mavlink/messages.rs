//! The messages the endpoint reads, decoded from checked frames by the `mavlink` crate's
//! common dialect (`MessageData::deser`, which zero-extends a MAVLink 2 payload whose trailing
//! zero bytes were dropped).

use super::frame::{Frame, Version};
use ::mavlink::dialects::common::{
    FOLLOW_TARGET_DATA, GLOBAL_POSITION_INT_DATA, HEARTBEAT_DATA, PARAM_REQUEST_LIST_DATA,
    PARAM_REQUEST_READ_DATA, PARAM_SET_DATA, VFR_HUD_DATA,
};
use ::mavlink::{MavlinkVersion, MessageData};

/// A message the endpoint uses.
#[derive(Clone, Debug, PartialEq)]
pub enum Message {
    /// A vehicle's position and heading (own state from the autopilot, or the target's).
    GlobalPosition(GLOBAL_POSITION_INT_DATA),
    /// A target's position, velocity and attitude.
    FollowTarget(FOLLOW_TARGET_DATA),
    /// Set one parameter.
    ParamSet(PARAM_SET_DATA),
    /// Read one parameter, by name or index.
    ParamRequestRead(PARAM_REQUEST_READ_DATA),
    /// Read every parameter.
    ParamRequestList(PARAM_REQUEST_LIST_DATA),
    /// A peer's heartbeat.
    Heartbeat(HEARTBEAT_DATA),
    /// The autopilot's airspeed (TC_VEHICLE 4's energy hold).
    VfrHud(VFR_HUD_DATA),
}

/// Why a checked frame did not decode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MessageError {
    /// Not a message the endpoint uses.
    Unknown(u32),
    /// A field out of its type's range (an enum value the dialect does not define).
    Malformed(u32),
}

/// The CRC_EXTRA of each message the endpoint decodes; `None` for the others.
pub fn extra_crc(message_id: u32) -> Option<u8> {
    Some(match message_id {
        GLOBAL_POSITION_INT_DATA::ID => GLOBAL_POSITION_INT_DATA::EXTRA_CRC,
        FOLLOW_TARGET_DATA::ID => FOLLOW_TARGET_DATA::EXTRA_CRC,
        PARAM_SET_DATA::ID => PARAM_SET_DATA::EXTRA_CRC,
        PARAM_REQUEST_READ_DATA::ID => PARAM_REQUEST_READ_DATA::EXTRA_CRC,
        PARAM_REQUEST_LIST_DATA::ID => PARAM_REQUEST_LIST_DATA::EXTRA_CRC,
        HEARTBEAT_DATA::ID => HEARTBEAT_DATA::EXTRA_CRC,
        VFR_HUD_DATA::ID => VFR_HUD_DATA::EXTRA_CRC,
        _ => return None,
    })
}

/// The message a checked frame carries.
pub fn decode(frame: &Frame<'_>) -> Result<Message, MessageError> {
    let version = match frame.version {
        Version::V1 => MavlinkVersion::V1,
        Version::V2 => MavlinkVersion::V2,
    };
    let id = frame.message_id;
    let payload = frame.payload;
    let malformed = |_| MessageError::Malformed(id);
    Ok(match id {
        GLOBAL_POSITION_INT_DATA::ID => Message::GlobalPosition(
            GLOBAL_POSITION_INT_DATA::deser(version, payload).map_err(malformed)?,
        ),
        FOLLOW_TARGET_DATA::ID => {
            Message::FollowTarget(FOLLOW_TARGET_DATA::deser(version, payload).map_err(malformed)?)
        }
        PARAM_SET_DATA::ID => {
            Message::ParamSet(PARAM_SET_DATA::deser(version, payload).map_err(malformed)?)
        }
        PARAM_REQUEST_READ_DATA::ID => Message::ParamRequestRead(
            PARAM_REQUEST_READ_DATA::deser(version, payload).map_err(malformed)?,
        ),
        PARAM_REQUEST_LIST_DATA::ID => Message::ParamRequestList(
            PARAM_REQUEST_LIST_DATA::deser(version, payload).map_err(malformed)?,
        ),
        HEARTBEAT_DATA::ID => {
            Message::Heartbeat(HEARTBEAT_DATA::deser(version, payload).map_err(malformed)?)
        }
        VFR_HUD_DATA::ID => {
            Message::VfrHud(VFR_HUD_DATA::deser(version, payload).map_err(malformed)?)
        }
        _ => return Err(MessageError::Unknown(id)),
    })
}
