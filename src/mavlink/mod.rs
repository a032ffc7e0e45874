//! The MAVLink 2 guidance endpoint's pure core (docs/mavlink.md): frames found in the byte
//! stream, the messages we use decoded from them with the `mavlink` crate's common dialect, one
//! message type at a time (its whole dialect costs 51 KB of flash), the parameters
//! ([`params`]), the frames we send, and the state machine that joins them ([`endpoint`]). The
//! board shells feed it bytes and a clock (`service`, with the `firmware` feature).

pub mod departure;
pub mod endpoint;
pub mod energy;
pub(crate) mod frame;
mod key_file;
pub(crate) mod messages;
pub(crate) mod outgoing;
pub mod params;
#[cfg(feature = "firmware")]
pub mod service;
mod setpoint;
pub mod signing;
#[cfg(feature = "mavlink-team")]
#[cfg_attr(docsrs, doc(cfg(feature = "mavlink-team")))]
pub mod team;
mod tracking;

pub use endpoint::{
    Endpoint, EndpointCounters, Halt, BOARD_NOTICE_MS, FALLBACK_CLOCK_TEXT, SIGNATURE_COUNTERS,
    UNSIGNED_TEXT,
};
pub use frame::{Frame, FrameCounters, FrameReader, Version};
pub use messages::{decode, extra_crc, Message, MessageError};
pub use outgoing::{Outbox, COMPONENT};
pub use params::{Params, Refusal, SPECS};
